"""Yunji commands about the robot's state and settings: ``robot_status`` (§3.3),
``robot_info`` (§3.4), ``software/get_version`` (§3.16.1), ``set_params`` / ``get_params``
(§3.11, §3.12)."""

from __future__ import annotations

import logging
import math

from polynav.errors import Conflict, InvalidRequest, NotFound
from polynav.protocols.yunji import containers
from polynav.protocols.yunji.context import (
    Context,
    Handler,
    Params,
    current_map,
    move_status_of,
    parse_float,
    pose_json,
    running_status,
)
from polynav.protocols.yunji.messages import Reply
from polynav.runtime.status import StatusSnapshot
from polynav.site import Point, PointKind

log = logging.getLogger(__name__)

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
            "move_status": containers.move_status(ctx, s, move_status.value),
            "running_status": containers.running_status(ctx, s, running_status(s)),
            "move_retry_times": int(s.retries),
            "charge_state": s.charging,
            "soft_estop_state": s.estop_software,
            "hard_estop_state": s.estop_hardware,
            "estop_state": s.estop_software or s.estop_hardware,
            "power_percent": int(round(s.battery_percent)),
            "current_pose": pose_json(s.pose),
            "current_floor": s.floor_level or 0,
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


def software_get_version(ctx: Context, params: Params) -> Reply:
    """§3.16.1: polynav's version."""
    return Reply(results=ctx.version)


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
        # ... and to the robot profile's limit (limits.max_linear_velocity and so on).
        ceiling = min(ceiling, getattr(ctx.runtime.profile.limits, setting))
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


HANDLERS: dict[str, Handler] = {
    "/api/robot_status": robot_status,
    "/api/robot_info": robot_info,
    "/api/set_params": set_params,
    "/api/get_params": get_params,
    "/api/software/get_version": software_get_version,
}
