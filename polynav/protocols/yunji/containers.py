"""Yunji containers and cabins (§D.8): docked to by a move to their markers, left before the
next move.

The API has no command for these dockings (§D.8: "presumably driven by marker types"), so the
adapter takes two custom marker types (custom types are > 1000, §3.5.1; docs/decisions.md):
:data:`CONTAINER_MARKER` for a container (a cart the robot lifts) and :data:`CABIN_MARKER` for a
mobile cabin (latched). A ``move`` to such a marker docks to the load standing there
(:meth:`polynav.runtime.cart_commands.CartCommands.dock`); a ``move`` started while the robot
carries a load first leaves it where it stands and then moves, as a move from the charging pile
first leaves the pile. Only translation lives here: the docking is the runtime's.

``running_status`` is ``dock_to_container`` / ``dock_to_cabin`` while a dock's seeing, driving
in and lifting or latching run, and ``leave_container`` / ``leave_cabin`` while a leave runs.
"""

from __future__ import annotations

from polynav.geometry import Pose2D
from polynav.nav.attempt import GoalOptions
from polynav.protocols.yunji.context import Context
from polynav.runtime.status import StatusSnapshot
from polynav.site import Point, PointKind

CONTAINER_MARKER = 1001
"""Marker type of a container (a cart lifted by the jack)."""
CABIN_MARKER = 1002
"""Marker type of a mobile cabin (latched)."""

_DOCKING = {"seeing", "entering", "taking"}
_KIND = {"cart": "container", "cabin": "cabin"}


def load_marker(point: Point) -> bool:
    """Whether ``point`` is a container's or a cabin's marker."""
    return point.kind is PointKind.CUSTOM and point.custom_type in (CONTAINER_MARKER,
                                                                   CABIN_MARKER)


def cart_task_id(count: int) -> str:
    """A dock's or leave's task id: its count with the top two bits set (never a move's or a
    cruise's)."""
    return f"{(3 << 126) | count:032X}"


def dock(ctx: Context, marker: str, cabin_id: str | None = None) -> None:
    """Dock to the load standing at ``marker`` (of the current map); a cabin's tag must read
    ``cabin_id`` when one is given (the move's ``cabin_id``, a polynav extension: the spec
    has no way to name the cabin expected, §D.8).

    Raises:
        InvalidRequest: nothing stands at the marker; a cabin id for a container.
        Conflict: a load heavier than the robot carries.
    """
    ctx.runtime.carts.dock(point=marker, cabin_id=cabin_id)


def leave_then_move(ctx: Context, point: str | None, pose: Pose2D | None,
                    map_name: str | None, options: GoalOptions) -> None:
    """Leave the load where the robot stands, then start the move (recorded for its
    notices' ``target``)."""
    def move() -> None:
        attempt = ctx.runtime.go_to(point=point, pose=pose,
                                    map_name=None if pose is not None else map_name,
                                    options=options)
        with ctx.lock:
            ctx.targets[attempt] = point or ""

    ctx.runtime.carts.leave(then=move)


def move_status(ctx: Context, snapshot: StatusSnapshot, default: str) -> str:
    """``default`` (the move's), or ``running`` while a dock or a leave runs, and ``failed``
    once one failed whose way there is the last move: the move task a client sent to a
    container's marker is done when the container is docked to."""
    carts = ctx.runtime.carts
    if carts.busy:
        return "running"
    outcome = carts.outcome(carts.count)
    if (outcome is not None and not outcome[0] and snapshot.attempt_id is not None
            and snapshot.attempt_id == carts.last_goal):
        return "failed"
    return default


def running_status(ctx: Context, snapshot: StatusSnapshot, default: str) -> str:
    """``default`` (the move's), or the dock or leave under way (§3.3 L242-L245)."""
    action = ctx.runtime.carts.status()["action"]
    if not isinstance(action, dict):
        return default
    load = _KIND.get(str(action.get("load")), "container")
    if action.get("action") == "leave" and action.get("phase") != "carrying":
        return f"leave_{load}"
    if action.get("action") == "dock" and action.get("phase") in _DOCKING:
        return f"dock_to_{load}"
    return default
