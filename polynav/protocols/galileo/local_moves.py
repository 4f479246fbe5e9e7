"""Local-move tasks (galileo-http-b §12, E58–E62): short exact motions without planning.

A ``local_move_action`` turns by ``angle`` then drives ``distance`` with the runtime's local
moves (they stop short of obstacles). A ``local_move_target_action`` reaches a pose (frame
``map`` or ``base_link``) the same way: turn towards it, drive, turn to its heading, skipping
steps within the tolerances; ``ERROR`` when ``timeout`` passes first (the engine's ``FAIL``, shown
as ``ERROR`` in a plain task). ``method`` (lidar docking
aid) is accepted and echoed; polynav's local moves always check the scan. E60 ends with an
``io_action`` setting one of the base's outputs (the ``GET/POST /system/io`` bank).
"""

from __future__ import annotations

from typing import Any

from polynav.errors import InvalidRequest
from polynav.protocols.galileo import session as sessions
from polynav.protocols.galileo import task_objects as objects
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.endpoint import Reply, RouteList
from polynav.protocols.galileo.goals import nav_to_target
from polynav.protocols.galileo.params import Params

ROUTES = RouteList()

LOCAL_MOVE_TASK = "local move task"


def _run(ctx: Context, actions: list[dict[str, Any]]) -> Reply:
    return objects.run(ctx, LOCAL_MOVE_TASK, actions, kind=objects.NAVIGATION)


def _local_move(params: Params) -> dict[str, Any]:
    distance, angle = params.number("distance"), params.number("angle")
    method = params.integer("method")
    if method not in (0, 1):
        raise InvalidRequest("method", f"must be 0 (none) or 1 (lidar), got {method}")
    if abs(distance) > 10.0:
        raise InvalidRequest("distance", f"a local move is at most 10 m, got {distance}")
    return {"type": "local_move_action", "angle": angle, "distance": distance, "method": method}


@ROUTES.get("/navigation/start_local_move")
def start_local_move(ctx: Context, params: Params) -> Reply:
    """E58."""
    action = _local_move(params)
    sessions.require_goals_allowed(ctx)
    return _run(ctx, [action])


@ROUTES.get("/navigation/start_nav_and_local_move")
def start_nav_and_local_move(ctx: Context, params: Params) -> Reply:
    """E59: to target ``index`` of the path in use, then the local move."""
    move = _local_move(params)
    map_name = sessions.current_map(ctx)
    nav = nav_to_target(ctx, map_name, sessions.current_path(ctx, map_name),
                        params.integer("index"))
    sessions.require_goals_allowed(ctx)
    return _run(ctx, [nav, move])


def _io(ctx: Context, params: Params) -> dict[str, Any]:
    """The ``io_action`` of E60: ``level`` "0"/"1" and ``port`` one of the base's outputs
    ("1".."3"); strings or ints (A-25). Checked before anything moves."""
    level, port = params.integer("level"), params.integer("port")
    if level not in (0, 1):
        raise InvalidRequest("level", f"an IO level is 0 (low) or 1 (high), got {level}")
    ports = ctx.runtime.peripherals.io_bank("io").output_ports
    if port not in ports:
        raise InvalidRequest("port", f"the IO ports are {ports.start}..{ports.stop - 1}, "
                                     f"got {port}")
    return {"type": "io_action", "level": str(level), "port": str(port)}


@ROUTES.get("/navigation/start_nav_local_move_io")
def start_nav_local_move_io(ctx: Context, params: Params) -> Reply:
    """E60: to target ``index`` of the path in use, the local move, then set IO ``port`` to
    ``level`` (an IO level here, not a floor)."""
    move, io = _local_move(params), _io(ctx, params)
    map_name = sessions.current_map(ctx)
    nav = nav_to_target(ctx, map_name, sessions.current_path(ctx, map_name),
                        params.integer("index"))
    sessions.require_goals_allowed(ctx)
    return _run(ctx, [nav, move, io])


def _tolerance(params: Params, name: str, default: float | None = None) -> float:
    value = params.number(name) if default is None else params.number(name, default)
    if not 0.0 < value <= 5.0:
        raise InvalidRequest(name, f"must be in (0, 5], got {value}")
    return float(value)


@ROUTES.get("/navigation/start_local_move_target")
def start_local_move_target(ctx: Context, params: Params) -> Reply:
    """E61."""
    frame = params.text("frame_id")
    if frame not in ("map", "base_link"):
        raise InvalidRequest("frame_id", f"must be 'map' or 'base_link', got {frame!r}")
    timeout = params.number("timeout")
    if not 0.0 < timeout <= 3600.0:
        raise InvalidRequest("timeout", f"must be in (0, 3600] s, got {timeout}")
    action = {
        "type": "local_move_target_action", "x": params.number("x"), "y": params.number("y"),
        "theta": params.number("theta"), "frame_id": frame,
        "xy_tolerance": _tolerance(params, "xy_tolerance"),
        "yaw_tolerance": _tolerance(params, "yaw_tolerance"), "timeout": timeout,
        "start_rotate_enable": params.boolean("start_rotate_enable"),
        "target_rotate_enable": params.boolean("target_rotate_enable"),
    }
    sessions.require_goals_allowed(ctx)
    return _run(ctx, [action])


@ROUTES.get("/navigation/start_local_move_index")
def start_local_move_index(ctx: Context, params: Params) -> Reply:
    """E62: a local move to target ``index`` of the path in use (tolerances from its line)."""
    map_name = sessions.current_map(ctx)
    path = sessions.current_path(ctx, map_name)
    index = params.integer("index")
    point = sessions.target_point(ctx, map_name, path, index)
    stop = sessions.routes(ctx).route(map_name, path).stops[index] if index >= 0 else None
    xy = max(0.01, min(stop.error_x, stop.error_y)) if stop is not None else 0.05
    action = {
        "type": "local_move_target_action", "x": float(point.pose.x),
        "y": float(point.pose.y), "theta": float(point.pose.theta), "frame_id": "map",
        "xy_tolerance": xy, "yaw_tolerance": 0.05, "timeout": 120.0,
        "start_rotate_enable": params.boolean("start_rotate_enable"),
        "target_rotate_enable": params.boolean("target_rotate_enable"),
    }
    sessions.require_goals_allowed(ctx)
    return _run(ctx, [action])
