"""Navigation tasks to a pose or a target point (galileo-http-b E27, E30, E31).

Each endpoint builds a task of ``nav_action``s (:mod:`.actions`) and runs it at once; the task
is returned (``WORKING``) and can be polled with ``GET /api/v1/task?id=``. A goal on another map
than the one in use goes through the site's connections (:mod:`.crossing`).
"""

from __future__ import annotations

import logging

from polynav.errors import Conflict, InvalidRequest
from polynav.geometry import Pose2D, wrap_angle
from polynav.protocols.galileo import crossing
from polynav.protocols.galileo import session as sessions
from polynav.protocols.galileo.actions import Action, NavAction
from polynav.protocols.galileo.context import TARGET_WITHOUT_ID, Context, Target
from polynav.protocols.galileo.endpoint import Reply, RouteList
from polynav.protocols.galileo.params import Params
from polynav.protocols.galileo.tasks import book

log = logging.getLogger(__name__)

ROUTES = RouteList()

NAVIGATION_TASK = "navigation task"
MULTI_MAP_TASK = "multi map navigation task"


def nav_to_target(ctx: Context, map_name: str, path: str, index: int) -> NavAction:
    """A ``nav_action`` to target ``index`` of (map, path); ``galileo_status`` shows its index."""
    point = sessions.target_point(ctx, map_name, path, index)
    target = Target(index, map_name, path)
    return NavAction(pose=point.pose, point=point.name, map_name=map_name, path=path,
                     index=index, on_attempt=lambda a: ctx.remember_target(a, target))


def nav_to_pose(ctx: Context, pose: Pose2D, map_name: str | None = None) -> NavAction:
    target = Target(TARGET_WITHOUT_ID)
    return NavAction(pose=pose, map_name=map_name,
                     on_attempt=lambda a: ctx.remember_target(a, target))


def plan_actions(ctx: Context, map_name: str, final: NavAction) -> list[Action]:
    """``final`` alone on the current map; on another map, the crossing of the site's direct
    connections that leads to it, else ``final`` alone for the runtime's multi-map router to
    route (through lifts), which refuses a map it cannot reach."""
    here = sessions.current_map(ctx)
    if map_name == here:
        return [final]
    try:
        return [*crossing.actions_between(ctx, here, map_name), final]
    except Conflict:
        log.info("galileo: no direct connections from %s to %s: the runtime routes", here,
                 map_name)
        return [final]


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
    actions = plan_actions(ctx, map_name, nav_to_pose(ctx, pose, map_name))
    return book(ctx).run(NAVIGATION_TASK, actions)


@ROUTES.get("/navigation/move_to_index")
def move_to_index(ctx: Context, params: Params) -> Reply:
    """E30: go to target ``index`` of (map, path) (default: the ones in use)."""
    index = params.integer("index")
    level = params.integer("level", None)
    map_name = params.text("map", None)
    if map_name is None and level is not None:
        map_name = crossing.map_of_level(ctx, level)
    map_name = map_name or sessions.current_map(ctx)
    path = params.text("path", None) or sessions.current_path(ctx, map_name)
    final = nav_to_target(ctx, map_name, path, index)  # NotFound / InvalidRequest first
    sessions.require_goals_allowed(ctx)
    actions = plan_actions(ctx, map_name, final)
    return book(ctx).run(NAVIGATION_TASK, actions)


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
    ``to`` across maps, built and not run (``WAITTING``)."""
    ends = []
    for name in ("from", "to"):
        map_name, path, index, level = _end(params, name)
        if map_name is None and level is not None:
            map_name = crossing.map_of_level(ctx, level)
        map_name = map_name or sessions.current_map(ctx)
        path = path or sessions.current_path(ctx, map_name)
        ends.append(nav_to_target(ctx, map_name, path, index))
    start, goal = ends
    assert start.map_name is not None and goal.map_name is not None
    actions: list[Action] = [start]
    if start.map_name != goal.map_name:
        actions.extend(crossing.actions_between(ctx, start.map_name, goal.map_name))
    actions.append(goal)
    return book(ctx).build(MULTI_MAP_TASK, actions, kind="navigation")


@ROUTES.get("/navigation/stop_nav_task")
def stop_nav_task(ctx: Context, params: Params) -> Reply:
    """E31: cancel the running navigation task; the task, ``null`` when there was none."""
    return book(ctx).cancel(kind="navigation")
