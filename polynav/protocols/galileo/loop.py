"""The loop task (galileo-http-b §1.10, E32–E34): the target points of the path in use, in
index order, waiting ``wait_time`` seconds at each, round after round until stopped.

It is a plain task with ``loop_flag: true`` (one ``nav_action`` and one ``sleep_action`` per
point) on the task engine; ``loop_count`` counts the rounds done. At most one
exists at a time (doc 4079): a second ``POST`` while one runs is HTTP 409.
"""

from __future__ import annotations

from typing import Any

from polynav.errors import Conflict, InvalidRequest
from polynav.protocols.galileo import session as sessions
from polynav.protocols.galileo import task_objects as objects
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.endpoint import Reply, RouteList
from polynav.protocols.galileo.goals import nav_to_target
from polynav.protocols.galileo.params import Params

ROUTES = RouteList()

LOOP_TASK = "loop task"
MAX_WAIT = 86_400.0  # [s]


@ROUTES.get("/navigation/loop_task")
def get_loop_task(ctx: Context, params: Params) -> Reply:
    """E32: the running loop task, else the last one, else ``null``."""
    task = objects.running(ctx, objects.LOOP) or objects.last(ctx, objects.LOOP)
    return None if task is None else objects.render(task)


@ROUTES.post("/navigation/loop_task")
def post_loop_task(ctx: Context, params: Params) -> Reply:
    """E33: start looping over the target points of the path in use."""
    wait_time = params.number("wait_time")
    if not 0.0 <= wait_time <= MAX_WAIT:
        raise InvalidRequest("wait_time", f"must be in [0, {MAX_WAIT:g}] s, got {wait_time}")
    sessions.require_goals_allowed(ctx)
    if objects.running(ctx, objects.LOOP) is not None:
        raise Conflict("loop task already exists")
    map_name = sessions.current_map(ctx)
    path = sessions.current_path(ctx, map_name)
    count = len(sessions.routes(ctx).route(map_name, path).stops)
    if count == 0:
        raise Conflict(f"path {path!r} of map {map_name!r} has no target points")
    actions: list[dict[str, Any]] = []
    for index in range(count):
        actions.append(nav_to_target(ctx, map_name, path, index))
        actions.append({"type": "sleep_action", "wait_time": wait_time})
    return objects.run(ctx, LOOP_TASK, actions, kind=objects.LOOP, loop_flag=True)


@ROUTES.delete("/navigation/loop_task")
def delete_loop_task(ctx: Context, params: Params) -> Reply:
    """E34: stop the loop task; the task (``CANCELLED``), ``null`` when none ran."""
    return objects.cancel_running(ctx, objects.LOOP)
