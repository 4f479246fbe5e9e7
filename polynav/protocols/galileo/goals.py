"""Navigation tasks to a pose or a target point (galileo-http-b E27, E30, E31, E57).

Each endpoint builds a task of ``nav_action``s and runs it at once on the task engine
(:mod:`.task_objects`); the task is returned (``WORKING``) and can be polled with
``GET /api/v1/task?id=``. A goal on another map than the one in use is one ``nav_action`` with
its ``map``: the runtime's router takes the robot across the site's direct connections and
lifts, or refuses the goal with its reason (``NoRoute``, a 409).
"""

from __future__ import annotations

import logging
from typing import Any

from polynav.errors import InvalidRequest
from polynav.geometry import Pose2D, wrap_angle
from polynav.protocols.galileo import follow
from polynav.protocols.galileo import session as sessions
from polynav.protocols.galileo import task_objects as objects
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.endpoint import Reply, RouteList
from polynav.protocols.galileo.params import Params

log = logging.getLogger(__name__)

ROUTES = RouteList()

NAVIGATION_TASK = "navigation task"
MULTI_MAP_TASK = "multi map navigation task"


def nav_to_target(ctx: Context, map_name: str, path: str, index: int) -> dict[str, Any]:
    """A ``nav_action`` to target ``index`` of (map, path), at the point's pose; GalileoStatus
    shows its index while it runs.

    Raises:
        NotFound: unknown map, path or index.
        InvalidRequest: a bad index.
    """
    pose = sessions.target_point(ctx, map_name, path, index).pose
    return {"type": "nav_action", "x": float(pose.x), "y": float(pose.y),
            "theta": float(pose.theta), "map": map_name, "path": path, "index": index}


def nav_to_pose(pose: Pose2D, map_name: str) -> dict[str, Any]:
    return {"type": "nav_action", "x": float(pose.x), "y": float(pose.y),
            "theta": float(pose.theta), "map": map_name}


def plan_actions(ctx: Context, map_name: str, final: dict[str, Any], path: str | None = None
                 ) -> list[dict[str, Any]]:
    """``final`` after the legs along the drawn path when the robot follows drawn paths on the
    map in use; on another map ``final`` alone, for the runtime's router."""
    here = sessions.current_map(ctx)
    if map_name != here:
        return [final]
    goal = Pose2D(final["x"], final["y"], final["theta"])
    legs = follow.waypoint_actions(ctx, map_name, path or sessions.current_path(ctx, here), goal)
    return [*legs, final]


@ROUTES.post("/navigation/start_nav_task")
def start_nav_task(ctx: Context, params: Params) -> Reply:
    """E27: go to ``x, y, theta`` [m, m, rad] on the current map, or on ``map``."""
    pose = Pose2D(params.number("x"), params.number("y"), wrap_angle(params.number("theta")))
    sessions.require_goals_allowed(ctx)
    map_name = params.text("map", None) or sessions.current_map(ctx)
    path = params.text("path", None)
    ctx.store.map_record(map_name)
    if path is not None:
        sessions.routes(ctx).route(map_name, path)
    actions = plan_actions(ctx, map_name, nav_to_pose(pose, map_name), path)
    return objects.run(ctx, NAVIGATION_TASK, actions, kind=objects.NAVIGATION)


@ROUTES.get("/navigation/move_to_index")
def move_to_index(ctx: Context, params: Params) -> Reply:
    """E30: go to target ``index`` of (map, path) (default: the ones in use)."""
    index = params.integer("index")
    level = params.integer("level", None)
    map_name = params.text("map", None)
    if map_name is None and level is not None:
        map_name = sessions.map_of_level(ctx, level)
    map_name = map_name or sessions.current_map(ctx)
    path = params.text("path", None) or sessions.current_path(ctx, map_name)
    final = nav_to_target(ctx, map_name, path, index)  # NotFound / InvalidRequest first
    sessions.require_goals_allowed(ctx)
    actions = plan_actions(ctx, map_name, final, path)
    return objects.run(ctx, NAVIGATION_TASK, actions, kind=objects.NAVIGATION)


def _end(params: Params, name: str) -> tuple[str | None, str | None, int, int | None]:
    raw = params.structure(name)
    if not isinstance(raw, dict):
        raise InvalidRequest(name, "must be an object {map, path, index[, level]}")
    inner = Params(raw)
    return (inner.text("map", None), inner.text("path", None), inner.integer("index"),
            inner.integer("level", None))


@ROUTES.post("/navigation/multi_map_task")
@ROUTES.get("/navigation/multi_map_task")
def multi_map_task(ctx: Context, params: Params) -> Reply:
    """E57 (POST; GET with the objects as JSON text too, A-12): the task from ``from`` to
    ``to``, built and not run (``WAITTING``): a goal at each end, the second on its own map
    (the runtime's router crosses to it when the task runs)."""
    ends = []
    for name in ("from", "to"):
        map_name, path, index, level = _end(params, name)
        if map_name is None and level is not None:
            map_name = sessions.map_of_level(ctx, level)
        map_name = map_name or sessions.current_map(ctx)
        path = path or sessions.current_path(ctx, map_name)
        ends.append(nav_to_target(ctx, map_name, path, index))
    spec = {"name": MULTI_MAP_TASK, "sub_tasks": ends}
    return objects.render(objects.create(ctx, spec, kind=objects.NAVIGATION))


@ROUTES.get("/navigation/stop_nav_task")
def stop_nav_task(ctx: Context, params: Params) -> Reply:
    """E31: cancel the running navigation task; the task, ``null`` when there was none."""
    return objects.cancel_running(ctx, objects.NAVIGATION)
