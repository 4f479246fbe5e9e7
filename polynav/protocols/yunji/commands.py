"""The Yunji command table: path -> handler (STYLE R4; the only module that imports runtime).

A handler takes the :class:`Context` and the decoded parameters, converts units and terms, calls
one runtime command (or reads the status snapshot / site store) and returns a
:class:`~polynav.protocols.yunji.messages.Reply`. Handlers are synchronous: runtime commands wait
for the runtime's loop, so the server runs them on a worker thread. polynav exceptions propagate
and the server maps them with :mod:`polynav.protocols.yunji.errors`.

Decisions where the spec is silent (see ``docs/yunji.md``):

* Navigation mode: a Yunji robot is always ready to move on its current floor's map, while a
  polynav runtime starts FREE. :func:`prepare` (called once by ``serve``) starts navigation on
  the map of the floor the robot stands on when the runtime is FREE. Moves in any other mode are
  ``REQUEST_DENIED``.
* A move while ``move_status`` is ``running`` is ``REQUEST_DENIED`` (§A-M3: "refused"); the
  running move goes on. ``location`` wins over ``marker`` when both are given (§A-M1).
* Markers are the points of the current floor's map; floors are floor records' ``level``.
"""

from __future__ import annotations

import logging
import math
import threading
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace

from polynav.errors import Conflict, InvalidRequest, NotFound
from polynav.geometry import Pose2D, wrap_angle, yaw_to_quaternion
from polynav.nav.attempt import GoalOptions
from polynav.protocols.yunji.messages import MarkerType, MoveStatus, Reply
from polynav.runtime.robot_runtime import Mode, RobotRuntime
from polynav.runtime.status import StatusSnapshot
from polynav.site import Point, PointKind
from polynav.store.site_store import SiteStore
from polynav.tasks.patrol import FOREVER, PatrolPlan

log = logging.getLogger(__name__)

Params = Mapping[str, str]
Handler = Callable[["Context", Params], Reply]

# Joystick limits (§3.6): values beyond them are clamped, not refused.
JOY_MAX_LINEAR = 0.5
JOY_MAX_ANGULAR = 1.0
ANGLE_OFFSET_LIMIT = 3.14
# set_params (§3.11): the vendor's ranges (clamped), then polynav's setting of that name.
SPEED_PARAMS: dict[str, tuple[float, float, str]] = {
    "max_speed_linear": (0.1, 1.0, "max_linear_velocity"),
    "max_speed_angular": (0.5, 3.5, "max_angular_velocity"),
}
# polynav's own limits for those settings (the lower of the two applies, §3.11 L751).
SETTING_LIMITS: dict[str, tuple[float, float]] = {
    "max_linear_velocity": (0.1, 1.0),
    "max_angular_velocity": (0.2, 3.0),
}
DEFAULT_DISTANCE_THRESHOLD = 2.0

_KIND_BY_TYPE: dict[int, PointKind] = {
    MarkerType.GENERAL: PointKind.GENERAL,
    MarkerType.FRONT_DESK: PointKind.FRONT_DESK,
    MarkerType.LIFT_OUTSIDE: PointKind.LIFT_OUTSIDE,
    MarkerType.LIFT_INSIDE: PointKind.LIFT_INSIDE,
    MarkerType.GATE: PointKind.GATE,
    MarkerType.CHARGING_PILE: PointKind.CHARGER,
}
_TYPE_BY_KIND: dict[PointKind, int] = {
    PointKind.GENERAL: MarkerType.GENERAL,
    PointKind.INITIAL: MarkerType.GENERAL,
    PointKind.FRONT_DESK: MarkerType.FRONT_DESK,
    PointKind.CHARGER: MarkerType.CHARGING_PILE,
    PointKind.LIFT_OUTSIDE: MarkerType.LIFT_OUTSIDE,
    PointKind.LIFT_INSIDE: MarkerType.LIFT_INSIDE,
    PointKind.GATE: MarkerType.GATE,
    PointKind.CUSTOM: MarkerType.CUSTOM,
}
_RUNNING_STATUS = {"leave_charger": "leave_charging_pile", "dock": "dock_to_charging_pile"}
# Cruise (§3.1.2): the least and default pass tolerance [m], the default retries per leg.
CRUISE_MIN_TOLERANCE = 0.5
CRUISE_DEFAULT_RETRIES = 5
_MOVE_STATUS = {
    "idle": MoveStatus.IDLE,
    "running": MoveStatus.RUNNING,
    "paused": MoveStatus.RUNNING,
    "succeeded": MoveStatus.SUCCEEDED,
    "failed": MoveStatus.FAILED,
    "canceled": MoveStatus.CANCELED,
}


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
        store = self.runtime.store
        assert isinstance(store, SiteStore)
        return store


# -- parameters -------------------------------------------------------------------------------


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


# -- site terms -------------------------------------------------------------------------------


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


def _marker_type(point: Point) -> int:
    """The marker ``key``: the kind's type, a custom point's own number (>= 1000)."""
    if point.kind is PointKind.CUSTOM and point.custom_type is not None:
        return point.custom_type
    return int(_TYPE_BY_KIND.get(point.kind, MarkerType.GENERAL))


def _marker_json(ctx: Context, point: Point, level: int) -> dict[str, object]:
    x, y, z, w = yaw_to_quaternion(point.pose.theta)
    return {
        "floor": level,
        "pose": {
            "orientation": {"w": w, "x": x, "y": y, "z": z},
            "position": {"x": point.pose.x, "y": point.pose.y, "z": 0.0},
        },
        "marker_name": point.name,
        "key": _marker_type(point),
    }


def pose_json(pose: Pose2D) -> dict[str, float]:
    return {"x": float(pose.x), "y": float(pose.y), "theta": float(pose.theta)}


def move_status_of(snapshot: StatusSnapshot) -> MoveStatus:
    """The move task's status: the patrol's while a cruise is the last task (``running`` for
    the whole cruise, §3.1.2), else the navigation attempt's."""
    state = snapshot.patrol_state or snapshot.navigation_state
    return _MOVE_STATUS.get(state, MoveStatus.IDLE)


def running_status(snapshot: StatusSnapshot) -> str:
    """§3.3 ``running_status``: the attempt's phase while the move task runs, else ``idle``."""
    if move_status_of(snapshot) is not MoveStatus.RUNNING:
        return "idle"
    return _RUNNING_STATUS.get(snapshot.phase or "", "running")


def _cruise_task_id(patrol_id: int) -> str:
    """A cruise's task id: its patrol id with the top bit set, so it never equals a move's."""
    return f"{(1 << 127) | patrol_id:032X}"


def _task_id(attempt_id: int) -> str:
    """A 32-hex-digit task id (§3.1.1), unique for the runtime's lifetime and deterministic."""
    return f"{attempt_id:032X}"


# -- handlers ---------------------------------------------------------------------------------


def robot_status(ctx: Context, params: Params) -> Reply:
    """§3.3: the snapshot in Yunji terms."""
    s = ctx.runtime.status()
    move_status = move_status_of(s)
    target = s.goal_point
    if target is None and s.attempt_id is not None:
        with ctx.lock:
            target = ctx.targets.get(s.attempt_id)
    chargepile = "0"
    if s.charging:
        chargepile = _charge_pile_id(ctx, s)
    return Reply(
        results={
            "move_target": target or "",
            "move_status": move_status.value,
            "running_status": running_status(s),
            "move_retry_times": int(s.retries),
            "charge_state": s.charging,
            "soft_estop_state": s.estop_software,
            "hard_estop_state": s.estop_hardware,
            "estop_state": s.estop_software or s.estop_hardware,
            "power_percent": int(round(s.battery_percent)),
            "current_pose": pose_json(s.pose),
            "current_floor": floor_level(ctx, s.floor),
            "chargepile_id": chargepile,
            "error_code": "00000000",
        }
    )


def _charge_pile_id(ctx: Context, s: StatusSnapshot) -> str:
    """The ``num`` of the nearest charging-pile marker within 1 m, else ``"0"``."""
    try:
        points = ctx.store.points(map_name=current_map(ctx))
    except (NotFound, Conflict):
        return "0"
    best: tuple[float, Point] | None = None
    for p in points:
        if p.kind is PointKind.CHARGER:
            d = math.hypot(p.pose.x - s.pose.x, p.pose.y - s.pose.y)
            if d <= 1.0 and (best is None or d < best[0]):
                best = (d, p)
    if best is None or best[1].number is None:
        return "0"
    return str(best[1].number)


def robot_info(ctx: Context, params: Params) -> Reply:
    """§3.4."""
    return Reply(results={"product_id": ctx.product_id})


def move(ctx: Context, params: Params) -> Reply:
    """§3.1.1: to a marker or a location; with ``markers``, a cruise (§3.1.2)."""
    if "markers" in params:
        return cruise(ctx, params)
    location = params.get("location")
    marker = params.get("marker")
    if not location and not marker:
        raise InvalidRequest("marker", "marker or location is required")
    angle_offset = optional_float(params, "angle_offset", 0.0)
    assert angle_offset is not None
    if abs(angle_offset) > ANGLE_OFFSET_LIMIT:
        raise InvalidRequest("angle_offset", f"must be within [-3.14, 3.14], got {angle_offset}")
    options = _goal_options(params)
    _require_navigation(ctx)
    pose: Pose2D | None = None
    if location:
        raw = _location(location)
        pose = replace(raw, theta=wrap_angle(raw.theta + angle_offset))
        target = ""
    elif angle_offset != 0.0:
        assert marker is not None
        point = ctx.store.point(current_map(ctx), marker)
        pose = replace(point.pose, theta=wrap_angle(point.pose.theta + angle_offset))
        target = marker
    else:
        assert marker is not None
        target = marker
    # One move starts at a time: two clients cannot both pass the "running" check, and
    # pending_target is this move's (the snapshot is refreshed after each runtime command).
    with ctx.move_lock:
        _refuse_while_running(ctx)
        with ctx.lock:
            ctx.pending_target = target
        try:
            if pose is not None:
                attempt = ctx.runtime.go_to(pose=pose, options=options)
            else:
                attempt = ctx.runtime.go_to(point=target, options=options)
            with ctx.lock:
                ctx.targets[attempt] = target
        finally:
            with ctx.lock:
                ctx.pending_target = None
    return Reply(task_id=_task_id(attempt))


def cruise(ctx: Context, params: Params) -> Reply:
    """§3.1.2: rounds over ``markers`` of the current floor (a polynav patrol)."""
    names = tuple(name for name in required(params, "markers").split(","))
    if any(not name for name in names):
        raise InvalidRequest("markers", "marker names must not be empty")
    if len(names) < 2:
        raise InvalidRequest("markers", f"a cruise needs at least 2 markers, got {len(names)}")
    count = optional_int(params, "count", 1)
    assert count is not None
    if count == 0 or count < FOREVER:
        raise InvalidRequest("count", f"must be >= 1 or -1 (forever), got {count}")
    tolerance = optional_float(params, "distance_tolerance", CRUISE_MIN_TOLERANCE)
    assert tolerance is not None
    if tolerance < CRUISE_MIN_TOLERANCE:
        raise InvalidRequest(
            "distance_tolerance", f"must be >= {CRUISE_MIN_TOLERANCE}, got {tolerance}"
        )
    retries = optional_int(params, "max_continuous_retries", CRUISE_DEFAULT_RETRIES)
    if retries is not None and retries < 0:
        raise InvalidRequest("max_continuous_retries", f"must be >= 0, got {retries}")
    _require_navigation(ctx)
    with ctx.move_lock:
        _refuse_while_running(ctx)
        patrol = ctx.runtime.patrol(
            PatrolPlan(names, count=count, tolerance=tolerance),
            GoalOptions(max_retries=retries),
        )
    return Reply(task_id=_cruise_task_id(patrol))


def _require_navigation(ctx: Context) -> None:
    if not ctx.runtime.powered:
        raise Conflict("the robot is powered off")
    if ctx.runtime.mode is not Mode.NAVIGATING:
        raise Conflict(f"the robot is not ready to navigate (mode {ctx.runtime.mode.value})")


def _refuse_while_running(ctx: Context) -> None:
    if move_status_of(ctx.runtime.status()) is MoveStatus.RUNNING:
        raise Conflict("a move task is running: cancel it first")


def _location(text: str) -> Pose2D:
    parts = text.split(",")
    if len(parts) != 3:
        raise InvalidRequest("location", f"must be x,y,theta, got {text!r}")
    x, y, theta = (parse_float("location", part) for part in parts)
    return Pose2D(x, y, theta)


def _goal_options(params: Params) -> GoalOptions:
    """The per-goal options of §3.1.1 as polynav's (see docs/yunji.md for the mapping)."""
    tolerances: dict[str, float] = {}
    for name in ("distance_tolerance", "theta_tolerance"):
        value = optional_float(params, name)
        if value is not None:
            if not value > 0.0:
                raise InvalidRequest(name, f"must be > 0, got {value}")
            tolerances[name] = value
    occupied = optional_float(params, "occupied_tolerance")
    if occupied is not None and occupied < 0.1:
        raise InvalidRequest("occupied_tolerance", f"must be >= 0.1, got {occupied}")
    retries = optional_int(params, "max_continuous_retries")
    if retries is not None and retries < 0:
        raise InvalidRequest("max_continuous_retries", f"must be >= 0, got {retries}")
    reverse = optional_int(params, "yaw_goal_reverse_allowed")
    near = max(tolerances.get("distance_tolerance", 0.0), occupied or 0.0)
    return GoalOptions(
        yaw_tolerance=tolerances.get("theta_tolerance"),
        reverse_allowed=reverse == 1,
        near_tolerance=near if near > 0.0 else None,
        max_retries=retries,
    )


def move_cancel(ctx: Context, params: Params) -> Reply:
    """§3.2. Nothing to cancel is ``REQUEST_DENIED`` (§A-M4)."""
    ctx.runtime.cancel()
    return Reply()


def markers_query_list(ctx: Context, params: Params) -> Reply:
    """§3.5.2: keyed by name; without ``floor``, every floor (the current floor wins a name
    clash, §A-K6); ``null`` when there is none (§A-K5)."""
    level = optional_int(params, "floor")
    floors = ctx.store.floors()
    if level is not None:
        floors = [f for f in floors if f.level == level]
        if not floors:
            raise InvalidRequest("floor", f"no floor {level}")
    current = current_map(ctx)
    floors.sort(key=lambda f: f.map_name == current)
    results: dict[str, object] = {}
    for record in floors:
        for point in ctx.store.points(map_name=record.map_name):
            results[point.name] = _marker_json(ctx, point, record.level)
    return Reply(results=results or None)


def markers_insert(ctx: Context, params: Params) -> Reply:
    """§3.5.1: at the current pose, on the current map; an existing name is moved (§A-K1)."""
    name = required(params, "name")
    kind, custom = _kind(params)
    num = optional_int(params, "num", 1)
    map_name = current_map(ctx)
    point = Point(name, map_name, ctx.runtime.status().pose, kind, num, custom)
    try:
        ctx.store.point(map_name, name)
    except NotFound:
        ctx.store.add_point(point)
    else:
        ctx.store.update_point(map_name, name, point)
    return Reply()


def _kind(params: Params) -> tuple[PointKind, int | None]:
    """The point kind of ``type`` (§3.5.1), and the custom type number for types >= 1000."""
    marker_type = optional_int(params, "type", 0)
    assert marker_type is not None
    if marker_type >= MarkerType.CUSTOM:
        return PointKind.CUSTOM, marker_type
    kind = _KIND_BY_TYPE.get(marker_type)
    if kind is None:
        raise InvalidRequest(
            "type", f"must be 0, 1, 3, 4, 7, 11 or a custom type >= 1000, got {marker_type}"
        )
    return kind, None


def markers_delete(ctx: Context, params: Params) -> Reply:
    """§3.5.3: unknown name -> ``INVALID_REQUEST`` ``Marker Not Found``."""
    name = required(params, "name")
    ctx.store.delete_point(current_map(ctx), name)
    return Reply()


def markers_count(ctx: Context, params: Params) -> Reply:
    """§3.5.4: markers of the current map."""
    return Reply(results={"count": len(ctx.store.points(map_name=current_map(ctx)))})


def markers_query_brief(ctx: Context, params: Params) -> Reply:
    """§3.5.5: ``name -> "<type>-<floor>"`` over every floor (as ``query_list``)."""
    current = current_map(ctx)
    floors = sorted(ctx.store.floors(), key=lambda f: f.map_name == current)
    results: dict[str, object] = {}
    for record in floors:
        for point in ctx.store.points(map_name=record.map_name):
            results[point.name] = f"{_marker_type(point)}-{record.level}"
    return Reply(results=results)


def markers_insert_by_pose(ctx: Context, params: Params) -> Reply:
    """§3.5.6: at ``x, y, theta`` on ``floor`` (default: the current one); theta outside
    [-π, π] is refused rather than wrapped (§A-K4); an existing name on that map is moved."""
    name = required(params, "name")
    x = parse_float("x", required(params, "x"))
    y = parse_float("y", required(params, "y"))
    theta = parse_float("theta", required(params, "theta"))
    if abs(theta) > math.pi + 1e-9:
        raise InvalidRequest("theta", f"must be within [-pi, pi], got {theta}")
    kind, custom = _kind(params)
    num = optional_int(params, "num", 1)
    level = optional_int(params, "floor")
    map_name = current_map(ctx) if level is None else map_of_level(ctx, level)
    point = Point(name, map_name, Pose2D(x, y, theta), kind, num, custom)
    try:
        ctx.store.point(map_name, name)
    except NotFound:
        ctx.store.add_point(point)
    else:
        ctx.store.update_point(map_name, name, point)
    return Reply()


def position_adjust(ctx: Context, params: Params) -> Reply:
    """§3.8.1: "the robot is at this marker" (of the current map)."""
    name = required(params, "marker")
    point = ctx.store.point(current_map(ctx), name)
    ctx.runtime.set_initial_pose(point.pose)
    return Reply()


def position_adjust_by_pose(ctx: Context, params: Params) -> Reply:
    """§3.8.2: "the robot is at this pose"; on another ``floor`` navigation restarts on that
    floor's map from the pose (the simulator carries the robot there)."""
    pose = Pose2D(
        parse_float("x", required(params, "x")),
        parse_float("y", required(params, "y")),
        parse_float("theta", required(params, "theta")),
    )
    level = optional_int(params, "floor")
    current = current_map(ctx)
    target = current if level is None else map_of_level(ctx, level)
    if target == current and ctx.runtime.mode is Mode.NAVIGATING:
        ctx.runtime.set_initial_pose(pose)
    else:
        ctx.runtime.start_navigation(target, pose=pose)
    return Reply()


def map_list(ctx: Context, params: Params) -> Reply:
    """§3.14.1: ``map name -> [floors]``; in polynav a map belongs to one floor at most."""
    levels = {f.name: f.level for f in ctx.store.floors()}
    return Reply(
        results={
            m.name: ([levels[m.floor]] if m.floor in levels else []) for m in ctx.store.maps()
        }
    )


def set_params(ctx: Context, params: Params) -> Reply:
    """§3.11: clamp to the vendor's range, then to polynav's; ``OK`` whatever the outcome
    (§A-P1): a bad value or an unknown name is logged and skipped."""
    changes: dict[str, object] = {}
    for name, text in params.items():
        if name == "uuid":
            continue
        spec = SPEED_PARAMS.get(name)
        if spec is None:
            log.info("yunji set_params: ignoring %s=%r (not supported)", name, text)
            continue
        low, high, setting = spec
        try:
            value = parse_float(name, text)
        except InvalidRequest as exc:
            log.info("yunji set_params: ignoring %s", exc)
            continue
        value = min(high, max(low, value))
        floor, ceiling = SETTING_LIMITS[setting]
        changes[setting] = min(ceiling, max(floor, value))
    if changes:
        ctx.runtime.update_settings(changes)
    return Reply()


def get_params(ctx: Context, params: Params) -> Reply:
    """§3.12: the current values (set or default, §A-P2)."""
    settings = ctx.runtime.settings()
    return Reply(
        results={
            "max_speed_linear": settings.max_linear_velocity,
            "max_speed_angular": settings.max_angular_velocity,
        }
    )


def map_list_info(ctx: Context, params: Params) -> Reply:
    """§3.14.4: ``map name -> [{floor, resolution, height, width, origin_x, origin_y}]``."""
    levels = {f.name: f.level for f in ctx.store.floors()}
    results: dict[str, object] = {}
    for m in ctx.store.maps():
        results[m.name] = [
            {
                "floor": levels[m.floor],
                "resolution": m.resolution,
                "height": m.height,
                "width": m.width,
                "origin_x": m.origin.x,
                "origin_y": m.origin.y,
            }
        ] if m.floor in levels else []
    return Reply(results=results)


def map_set_current_map(ctx: Context, params: Params) -> Reply:
    """§3.14.2: navigate on ``map_name`` (or the deprecated ``hotel_id``, §A-P3) at ``floor``,
    which must be that map's floor. Refused while a move runs, as a move is."""
    name = params.get("map_name") or params.get("hotel_id")
    if not name:
        raise InvalidRequest("map_name", "is required")
    level = optional_int(params, "floor")
    if level is None:
        raise InvalidRequest("floor", "is required")
    record = ctx.store.map_record(name)
    levels = {f.name: f.level for f in ctx.store.floors()}
    if record.floor not in levels or levels[record.floor] != level:
        raise InvalidRequest("floor", f"map {name!r} is not on floor {level}")
    if move_status_of(ctx.runtime.status()) is MoveStatus.RUNNING:
        raise Conflict("a move task is running: cancel it first")
    ctx.runtime.start_navigation(name)
    return Reply()


def estop(ctx: Context, params: Params) -> Reply:
    """§3.7: the software e-stop only; the hardware button is separate."""
    ctx.runtime.set_software_estop(required_bool(params, "flag"))
    return Reply()


def joy_control(ctx: Context, params: Params) -> Reply:
    """§3.6: clamped to ±0.5 m/s and ±1.0 rad/s; one command holds 0.5 s (the runtime's
    dead-man). A running move is not overridden: ``REQUEST_DENIED`` (§A-M12)."""
    linear = parse_float("linear_velocity", required(params, "linear_velocity"))
    angular = parse_float("angular_velocity", required(params, "angular_velocity"))
    linear = max(-JOY_MAX_LINEAR, min(JOY_MAX_LINEAR, linear))
    angular = max(-JOY_MAX_ANGULAR, min(JOY_MAX_ANGULAR, angular))
    ctx.runtime.teleop(linear, angular)
    return Reply()


def get_current_location(ctx: Context, params: Params) -> Reply:
    """§3.23: every marker of the current map within ``distance_threshold``, nearest first."""
    threshold = optional_float(params, "distance_threshold", DEFAULT_DISTANCE_THRESHOLD)
    assert threshold is not None
    if threshold < 0.01:
        raise InvalidRequest("distance_threshold", f"must be >= 0.01, got {threshold}")
    s = ctx.runtime.status()
    near: list[tuple[float, Point]] = []
    for p in ctx.store.points(map_name=current_map(ctx)):
        d = math.hypot(p.pose.x - s.pose.x, p.pose.y - s.pose.y)
        if d <= threshold:
            near.append((d, p))
    near.sort(key=lambda item: item[0])
    return Reply(
        results={
            "current_floor": floor_level(ctx, s.floor),
            "current_pose": pose_json(s.pose),
            "near_markers": [
                {"distance": d, "key": _marker_type(p), "marker_name": p.name} for d, p in near
            ],
            "running_status": running_status(s),
        }
    )


def map_get_current_map(ctx: Context, params: Params) -> Reply:
    """§3.14.3: ``floor`` is a string as in the spec's example (§A-J4)."""
    s = ctx.runtime.status()
    record = ctx.store.map_record(current_map(ctx))
    return Reply(
        results={
            "hotel_id": record.name,
            "map_name": record.name,
            "floor": str(floor_level(ctx, s.floor)),
            "info": {
                "resolution": record.resolution,
                "width": record.width,
                "height": record.height,
                "origin_x": record.origin.x,
                "origin_y": record.origin.y,
            },
        }
    )


def software_get_version(ctx: Context, params: Params) -> Reply:
    """§3.16.1: polynav's version."""
    return Reply(results=ctx.version)


HANDLERS: dict[str, Handler] = {
    "/api/robot_status": robot_status,
    "/api/robot_info": robot_info,
    "/api/move": move,
    "/api/move/cancel": move_cancel,
    "/api/markers/query_list": markers_query_list,
    "/api/markers/insert": markers_insert,
    "/api/markers/delete": markers_delete,
    "/api/markers/count": markers_count,
    "/api/markers/query_brief": markers_query_brief,
    "/api/markers/insert_by_pose": markers_insert_by_pose,
    "/api/position_adjust": position_adjust,
    "/api/position_adjust_by_pose": position_adjust_by_pose,
    "/api/map/list": map_list,
    "/api/map/list_info": map_list_info,
    "/api/map/set_current_map": map_set_current_map,
    "/api/set_params": set_params,
    "/api/get_params": get_params,
    "/api/estop": estop,
    "/api/joy_control": joy_control,
    "/api/get_current_location": get_current_location,
    "/api/map/get_current_map": map_get_current_map,
    "/api/software/get_version": software_get_version,
}


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
