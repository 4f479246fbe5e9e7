"""Yunji commands that move the robot: ``move`` to a marker or a location and the cruise
(§3.1), ``move/cancel`` (§3.2), ``joy_control`` (§3.6), ``estop`` (§3.7) and the position
corrections (§3.8).

A move while ``move_status`` is ``running`` is ``REQUEST_DENIED`` (§A-M3: "refused"); the
running move goes on. ``location`` wins over ``marker`` when both are given (§A-M1). Moves in
any mode but navigating are ``REQUEST_DENIED``.
"""

from __future__ import annotations

from dataclasses import replace

from polynav.errors import Conflict, InvalidRequest, NotFound
from polynav.geometry import Pose2D, wrap_angle
from polynav.nav.attempt import GoalOptions
from polynav.protocols.yunji import containers
from polynav.protocols.yunji.context import (
    Context,
    Handler,
    Params,
    current_map,
    map_of_level,
    move_status_of,
    optional_float,
    optional_int,
    parse_float,
    required,
    required_bool,
)
from polynav.protocols.yunji.messages import MoveStatus, Reply
from polynav.runtime.config import Mode
from polynav.tasks.patrol import FOREVER, PatrolPlan

# Joystick limits (§3.6): values beyond them are clamped, not refused.
JOY_MAX_LINEAR = 0.5
JOY_MAX_ANGULAR = 1.0
ANGLE_OFFSET_LIMIT = 3.14
# Cruise (§3.1.2): the least and default pass tolerance [m], the default retries per leg.
CRUISE_MIN_TOLERANCE = 0.5
CRUISE_DEFAULT_RETRIES = 5


def _task_id(attempt_id: int) -> str:
    """A 32-hex-digit task id (§3.1.1), unique for the runtime's lifetime and deterministic."""
    return f"{attempt_id:032X}"


def _cruise_task_id(patrol_id: int) -> str:
    """A cruise's task id: its patrol id with the top bit set, so it never equals a move's."""
    return f"{(1 << 127) | patrol_id:032X}"


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
        carts = ctx.runtime.carts
        if carts.busy:
            raise Conflict("a container or cabin is being docked to or left")
        if carts.load is not None:  # docked: leave it first (§D.8), as a charging pile
            containers.leave_then_move(ctx, target or None, pose,
                                       _map_of(ctx, target) if target else None, options)
            return Reply(task_id=containers.cart_task_id(carts.count))
        if pose is None and containers.load_marker(
                ctx.store.point(_map_of(ctx, target), target)):
            containers.dock(ctx, target, params.get("cabin_id") or None)
            return Reply(task_id=containers.cart_task_id(carts.count))
        with ctx.lock:
            ctx.pending_target = target
        try:
            if pose is not None:
                attempt = ctx.runtime.go_to(pose=pose, options=options)
            else:
                attempt = ctx.runtime.go_to(point=target, map_name=_map_of(ctx, target),
                                            options=options)
            with ctx.lock:
                ctx.targets[attempt] = target
        finally:
            with ctx.lock:
                ctx.pending_target = None
    return Reply(task_id=_task_id(attempt))


def _map_of(ctx: Context, marker: str) -> str:
    """The map of ``marker``: the current floor's when it has one of that name, else the one
    floor that has it (a move there rides the lifts, §1.3 L686).

    Raises:
        NotFound: no floor has it. Conflict: several other floors have it.
    """
    here = current_map(ctx)
    try:
        ctx.store.point(here, marker)
        return here
    except NotFound:
        return ctx.store.find_point(marker).map_name


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
    """§3.2. Nothing to cancel is ``REQUEST_DENIED`` (§A-M4); a dock to or a leave of a
    container or cabin under way is the move task, and stops (01062/01082, 01052/01072)."""
    if ctx.runtime.carts.cancel():
        return Reply()
    ctx.runtime.cancel()
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


HANDLERS: dict[str, Handler] = {
    "/api/move": move,
    "/api/move/cancel": move_cancel,
    "/api/position_adjust": position_adjust,
    "/api/position_adjust_by_pose": position_adjust_by_pose,
    "/api/estop": estop,
    "/api/joy_control": joy_control,
}
