"""Navigation lifecycle and status endpoints (galileo-http-b §4, E37, E49, E56).

``navigation/start`` loads a map and localizes (runtime ``start_navigation``), ``stop`` unloads
it; the read-outs come from the status snapshot. Decisions (``docs/galileo.md``):

* ``start`` with a missing ``map``/``path`` uses the session's (:mod:`.session`); with no
  ``start_index`` polynav localizes by itself (in simulation: where the robot stands; A-33 asks
  for an error on a lidar robot, which would stop scripts that run out of the box). While
  navigating, ``start`` restarts on the given map (the runtime reloads). ``level`` picks the
  map of that floor when ``map`` is missing.
* ``stop`` answers ``{"result": true}`` even when nothing navigates (issue item 11: scripts call
  it first); the description says so.
* ``pose`` answers in any state (the robot always knows a pose); ``angle`` is in degrees.
* ``update_map``: polynav does not update a map while navigating; turning it on is refused
  with a clear error, and the read-out is ``false``.
* ``start_schedule_mode`` starts navigation like ``start`` with no parameters and puts the
  adapter in dispatch mode, where Galileo goal endpoints refuse (A-28).
"""

from __future__ import annotations

import logging
import math

from polynav.errors import Conflict, InvalidRequest
from polynav.geometry import Pose2D, wrap_angle
from polynav.protocols.galileo import session as sessions
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.endpoint import Reply, RouteList
from polynav.protocols.galileo.params import Params

log = logging.getLogger(__name__)

ROUTES = RouteList()


def start(ctx: Context, params: Params) -> dict[str, object]:
    """Start navigation on (map, path) from ``start_index``; the session remembers them."""
    s = sessions.session(ctx)
    level = params.integer("level", None)
    map_name = params.text("map", None)
    if map_name is None and level is not None:
        map_name = sessions.map_of_level(ctx, level)
    map_name = map_name or sessions.current_map(ctx)
    ctx.store.map_record(map_name)  # NotFound before anything changes
    path = params.text("path", None) or sessions.current_path(ctx, map_name)
    sessions.routes(ctx).route(map_name, path)
    start_index, point = sessions.start_point(ctx, params, map_name, path)
    if ctx.runtime.status().mode == "mapping":
        raise Conflict("the robot is mapping: stop mapping first")
    ctx.runtime.tasks.cancel_running()
    ctx.runtime.start_navigation(map_name, point=point)
    with s.lock:
        s.map_name = map_name
        s.paths[map_name] = path
        if start_index is not None:
            s.start_index = start_index
    log.info("galileo: navigation on %s/%s from %s", map_name, path, start_index)
    return {"result": True, "description": ""}


@ROUTES.get("/navigation/start", result_errors=True)
def navigation_start(ctx: Context, params: Params) -> Reply:
    """E9."""
    if sessions.session(ctx).dispatch:
        raise Conflict("the robot is in dispatch mode: stop_schedule_mode first")
    return start(ctx, params)


@ROUTES.get("/navigation/stop", result_errors=True)
def navigation_stop(ctx: Context, params: Params) -> Reply:
    """E13: cancels every task, unloads the map; ``result: true`` also when not navigating."""
    snap = ctx.runtime.status()
    ctx.runtime.tasks.cancel_running()
    if snap.mode == "mapping":
        raise Conflict("the robot is mapping, not navigating: use /api/v1/map/stop")
    if snap.mode != "navigating":
        return {"result": True, "description": "navigation was not running"}
    ctx.runtime.stop_navigation()
    return {"result": True, "description": ""}


@ROUTES.get("/navigation/start_schedule_mode", result_errors=True)
def start_schedule_mode(ctx: Context, params: Params) -> Reply:
    """E12: navigation on the current map and path, Galileo goals refused until stopped."""
    s = sessions.session(ctx)
    if s.dispatch:
        return {"result": True, "description": "already in dispatch mode"}
    reply = start(ctx, Params({}))
    s.dispatch = True
    return reply


@ROUTES.get("/navigation/stop_schedule_mode", result_errors=True)
def stop_schedule_mode(ctx: Context, params: Params) -> Reply:
    """E14."""
    s = sessions.session(ctx)
    if not s.dispatch:
        raise Conflict("the robot is not in dispatch mode")
    s.dispatch = False
    if ctx.runtime.status().mode == "navigating":
        ctx.runtime.stop_navigation()
    return {"result": True, "description": ""}


@ROUTES.put("/navigation/update_map")
def put_update_map(ctx: Context, params: Params) -> Reply:
    """E10: refused when asked to turn on (polynav keeps maps fixed while navigating)."""
    if params.boolean("enabled"):
        raise Conflict("polynav does not update the map while navigating; to change a map, "
                       "map the place anew with /api/v1/map/start and save it under its name")
    return {"enabled": False}


@ROUTES.get("/navigation/update_map", inline=True)
def get_update_map(ctx: Context, params: Params) -> Reply:
    """E11."""
    return {"enabled": False}


@ROUTES.get("/navigation/pose", inline=True)
def pose(ctx: Context, params: Params) -> Reply:
    """E15: ``{"x", "y", "angle"}`` with ``angle`` in degrees."""
    p = ctx.runtime.status().pose
    return {"x": float(p.x), "y": float(p.y), "angle": math.degrees(p.theta)}


@ROUTES.get("/navigation/current_path")
def current_path(ctx: Context, params: Params) -> Reply:
    """E16."""
    map_name = sessions.current_map(ctx)
    return {"map": map_name, "path": sessions.current_path(ctx, map_name)}


@ROUTES.get("/navigation/target_distance", inline=True)
def target_distance(ctx: Context, params: Params) -> Reply:
    """E17: the remaining path length [m] of the running goal, ``-1`` without one."""
    snap = ctx.runtime.status()
    distance = -1.0
    if snap.navigation_state in ("running", "paused"):
        if snap.distance_remaining is not None:
            distance = float(snap.distance_remaining)
        elif snap.goal is not None:
            distance = math.hypot(snap.goal.x - snap.pose.x, snap.goal.y - snap.pose.y)
    return {"distance": distance}


@ROUTES.get("/navigation/reload")
def reload(ctx: Context, params: Params) -> Reply:
    """E37: switch the navigation map (and path) while navigating."""
    map_name = params.text("map")
    ctx.store.map_record(map_name)
    path = params.text("path", None) or sessions.current_path(ctx, map_name)
    sessions.routes(ctx).route(map_name, path)
    if ctx.runtime.status().mode != "navigating":
        raise Conflict("navigation is not started: reload switches the map while navigating")
    s = sessions.session(ctx)
    ctx.runtime.tasks.cancel_running()
    ctx.runtime.start_navigation(map_name)
    with s.lock:
        s.map_name = map_name
        s.paths[map_name] = path
    return {"status": "ok", "map": map_name, "path": path}


@ROUTES.get("/navigation/switch_map")
def switch_map(ctx: Context, params: Params) -> Reply:
    """E49: the map the next ``navigation/start`` uses; refused while navigating (A-11)."""
    map_name = params.text("map_name")
    ctx.store.map_record(map_name)
    if ctx.runtime.status().mode == "navigating":
        raise Conflict("switch_map only changes the map file while not navigating; "
                       "use /api/v1/navigation/reload")
    s = sessions.session(ctx)
    with s.lock:
        s.map_name = map_name
    return {"status": "ok"}


@ROUTES.post("/navigation/init_pose")
def init_pose(ctx: Context, params: Params) -> Reply:
    """E56: relocalize at ``x, y`` with heading ``theta`` (else ``z`` when non-zero, else the
    current heading; A-5)."""
    x, y = params.number("x"), params.number("y")
    z = params.number("z", 0.0)
    if "theta" in params:
        theta = params.number("theta")
    elif z != 0.0:
        theta = z
    else:
        theta = ctx.runtime.status().pose.theta
    if ctx.runtime.status().mode != "navigating":
        raise Conflict("navigation is not started: the initial pose is on the navigation map")
    if not all(math.isfinite(v) for v in (x, y, theta)):
        raise InvalidRequest("x", "coordinates must be finite")
    ctx.runtime.set_initial_pose(Pose2D(x, y, wrap_angle(theta)))
    return {"status": "ok"}
