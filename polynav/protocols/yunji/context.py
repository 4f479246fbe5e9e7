"""What every Yunji command handler shares: the :class:`Context`, parameter parsing, and the
Yunji terms for polynav's (floors, the current map, move and running status).

A handler takes the :class:`Context` and the decoded parameters, converts units and terms, calls
one runtime command (or reads the status snapshot / site store) and returns a
:class:`~polynav.protocols.yunji.messages.Reply`. Handlers are synchronous: runtime commands wait
for the runtime's loop, so the server runs them on a worker thread. polynav exceptions propagate
and the server maps them with :mod:`polynav.protocols.yunji.errors`. The handlers are grouped by
subject (``robot``, ``moves``, ``markers``, ``maps``, ``streams``, ``device``, ``queries``) and
gathered by :mod:`~polynav.protocols.yunji.routes`.

Decisions where the spec is silent (see ``docs/yunji.md``):

* Navigation mode: a Yunji robot is always ready to move on its current floor's map, while a
  polynav runtime starts FREE. :func:`prepare` (called once by ``serve``) starts navigation on
  the map of the floor the robot stands on when the runtime is FREE.
* Markers are the points of the current floor's map; floors are floor records' ``level``.
"""

from __future__ import annotations

import logging
import math
import threading
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

from polynav.errors import Conflict, InvalidRequest, NotFound
from polynav.geometry import Pose2D
from polynav.protocols.site_store import site_store
from polynav.protocols.yunji.messages import MoveStatus, Reply
from polynav.runtime.config import Mode
from polynav.runtime.robot_runtime import RobotRuntime
from polynav.runtime.status import StatusSnapshot
from polynav.store.site_store import SiteStore

log = logging.getLogger(__name__)

Params = Mapping[str, str]
Handler = Callable[["Context", Params], Reply]

_MOVE_STATUS = {
    "idle": MoveStatus.IDLE,
    "running": MoveStatus.RUNNING,
    "paused": MoveStatus.RUNNING,
    "succeeded": MoveStatus.SUCCEEDED,
    "failed": MoveStatus.FAILED,
    "canceled": MoveStatus.CANCELED,
}

_RUNNING_STATUS = {"leave_charger": "leave_charging_pile", "dock": "dock_to_charging_pile"}
# polynav's lift phases (runtime.lift_events.LiftPhase) -> running_status (§3.3, L246-L253).
_LIFT_RUNNING_STATUS = {
    "going_to_lift": "goto_lift",
    "waiting_for_session": "wait_lift_unlock",
    "calling": "wait_lift_outside",
    "waiting_for_car": "wait_lift_outside",
    "entering": "enter_lift",
    "riding": "take_lift",
    "switching_map": "take_lift",
    "exiting": "exit_lift",
}
# Out of the car's way after a failed entry, back into it after a failed exit (L251, L253).
_LIFT_MANOEUVRE = {"avoiding": "avoid_lift", "backing_in": "back_to_lift"}


@dataclass
class Context:
    """What handlers share: the runtime and the server's own bookkeeping.

    Attributes:
        runtime: the robot.
        product_id: ``robot_info.product_id``.
        version: ``software/get_version`` result.
        targets: marker name (``""`` for a location) by runtime attempt id, for moves sent as a
            pose (``angle_offset``) whose snapshot and events carry no point name.
        pending_target: the target of the move being started (its attempt id is not known
            until ``go_to`` returns, but its start event is published during the call).
    """

    runtime: RobotRuntime
    product_id: str
    version: str
    targets: dict[int, str] = field(default_factory=dict)
    pending_target: str | None = None
    lock: threading.Lock = field(default_factory=threading.Lock)
    move_lock: threading.Lock = field(default_factory=threading.Lock)

    def target_of(self, attempt_id: int) -> str | None:
        """The marker an attempt was sent to by this adapter (``""``: a location), else the
        target of the move being started, else ``None``."""
        with self.lock:
            if attempt_id in self.targets:
                return self.targets[attempt_id]
            return self.pending_target

    @property
    def store(self) -> SiteStore:
        return site_store(self.runtime)


def required(params: Params, name: str) -> str:
    value = params.get(name)
    if value is None or value == "":
        raise InvalidRequest(name, "is required")
    return value


def optional_float(params: Params, name: str, default: float | None = None) -> float | None:
    text = params.get(name)
    if text is None:
        return default
    return parse_float(name, text)


def parse_float(name: str, text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise InvalidRequest(name, f"must be a number, got {text!r}") from None
    if not math.isfinite(value):
        raise InvalidRequest(name, f"must be finite, got {text!r}")
    return value


def optional_int(params: Params, name: str, default: int | None = None) -> int | None:
    text = params.get(name)
    if text is None:
        return default
    try:
        return int(text)
    except ValueError:
        raise InvalidRequest(name, f"must be an integer, got {text!r}") from None


def required_bool(params: Params, name: str) -> bool:
    text = required(params, name)
    if text not in ("true", "false"):
        raise InvalidRequest(name, f"must be true or false, got {text!r}")
    return text == "true"


def floor_level(ctx: Context, floor_name: str | None) -> int:
    if floor_name is None:
        return 0
    try:
        return int(ctx.store.floor(floor_name).level)
    except NotFound:
        return 0


def current_map(ctx: Context) -> str:
    """The map of the current floor: the navigation map, else the floor's map."""
    name = ctx.runtime.map_name
    if name is not None:
        return name
    floor = ctx.runtime.status().floor
    if floor is None:
        raise Conflict("the robot is on no known floor")
    return ctx.store.floor(floor).map_name


def map_of_level(ctx: Context, level: int) -> str:
    for record in ctx.store.floors():
        if record.level == level:
            return record.map_name
    raise InvalidRequest("floor", f"no floor {level}")


def pose_json(pose: Pose2D) -> dict[str, float]:
    return {"x": float(pose.x), "y": float(pose.y), "theta": float(pose.theta)}


def move_status_of(snapshot: StatusSnapshot) -> MoveStatus:
    """The move task's status: the patrol's while a cruise is the last task (``running`` for
    the whole cruise, §3.1.2), else the navigation attempt's."""
    state = snapshot.patrol_state or snapshot.navigation_state
    return _MOVE_STATUS.get(state, MoveStatus.IDLE)


def running_status(snapshot: StatusSnapshot) -> str:
    """§3.3 ``running_status``: the attempt's phase while the move task runs, else ``idle``;
    during a goal on another floor, the lift sequence's phase (``goto_lift`` ..
    ``exit_lift``, L246-L253)."""
    if move_status_of(snapshot) is not MoveStatus.RUNNING:
        return "idle"
    lift = (snapshot.route or {}).get("lift")
    if isinstance(lift, dict):
        manoeuvre = lift.get("manoeuvre")
        if manoeuvre is not None:
            return _LIFT_MANOEUVRE.get(str(manoeuvre), "running")
        lift_status = _LIFT_RUNNING_STATUS.get(str(lift.get("phase")))
        if lift_status is not None:
            return lift_status
    return _RUNNING_STATUS.get(snapshot.phase or "", "running")


def lift_car(snapshot: StatusSnapshot) -> str | None:
    """The car of the lift sequence under way, if any."""
    lift = (snapshot.route or {}).get("lift")
    return str(lift["car"]) if isinstance(lift, dict) and "car" in lift else None


def prepare(runtime: RobotRuntime) -> None:
    """Put a FREE runtime into navigation on the map of the floor it stands on (see module doc).

    A failure is logged, not raised: the server still answers, and moves are refused until
    navigation runs.
    """
    if runtime.mode is not Mode.FREE:
        return
    floor = runtime.status().floor
    store = runtime.store
    if floor is None or not isinstance(store, SiteStore):
        log.warning("yunji: cannot start navigation: no floor or no site store")
        return
    try:
        runtime.start_navigation(store.floor(floor).map_name)
    except (InvalidRequest, NotFound, Conflict) as exc:
        log.warning("yunji: cannot start navigation on floor %s: %s", floor, exc)
