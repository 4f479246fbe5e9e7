"""Tasks (puwei-api §8): ``POST /api/task/set``, ``GET /api/task/run/:name`` and
``GET /api/scheduler/release?map=``, on the runtime's task engine (no runner of our own).

A Puwei task is stored as an engine task (owner ``puwei``, the tree of
:mod:`polynav.protocols.puwei.convert`) with its schedules, so it survives a restart; its Puwei
``name`` is the key: setting a name again replaces that task (a running one is cancelled
first). The map navigation ran on when it was set is kept in its blackboard
(``puwei_map``) for ``scheduler/release``, which drops the schedules of that map's tasks (the
tasks stay, and ``task/run`` still runs them). Everything is checked before anything changes:
the body, the tree, the schedules, the stations on the map.
"""

from __future__ import annotations

import logging
from typing import Any

from polynav.errors import Conflict, InvalidRequest, NotFound
from polynav.protocols.puwei import convert
from polynav.protocols.puwei.context import Context
from polynav.protocols.puwei.endpoint import RouteList
from polynav.protocols.puwei.maps import site_store
from polynav.protocols.puwei.request import PuweiRequest
from polynav.protocols.puwei.robot import charger_point
from polynav.tasks import tree
from polynav.tasks.schedule import ScheduleSpec

log = logging.getLogger(__name__)

ROUTES = RouteList()

OWNER = "puwei"
KIND = "puwei_task"
MAP_KEY = "puwei_map"


def find(ctx: Context, name: str) -> dict[str, Any] | None:
    """The stored Puwei task named ``name``, if any."""
    for task in ctx.runtime.tasks.list(owner=OWNER, kind=KIND):
        if task["name"] == name:
            return task
    return None


@ROUTES.post("/api/task/set")
def set_task(ctx: Context, request: PuweiRequest) -> dict[str, Any]:
    """Set (or replace) task ``name``: mode 0 starts it now, 1-3 schedule it.

    ``data``: ``{"name", "id", "mode", "schedules": [next start ...]}`` (the document's is
    empty; the extra fields tell a client what was made).
    """
    rt = ctx.runtime
    body = request.json_object()
    snap = rt.status()
    task = convert.parse_task(body, charger=charger_point(ctx), now=rt.calendar_now())
    tree.build(task.tree)  # the engine's own check, before anything changes
    for spec in task.schedules:
        ScheduleSpec.from_json(spec)
    if task.stations:
        if snap.map is None:
            raise Conflict("topology stations are points of the map navigation runs on: "
                           "start navigation first")
        known = {p.name for p in rt.store.points(map_name=snap.map)}
        for station in task.stations:
            if station not in known:
                raise NotFound(f"station on map {snap.map!r}", station)
    if task.mode == convert.IMMEDIATE and snap.mode != "navigating":
        raise Conflict("an immediate task needs navigation (GET /api/roslaunch/navigation/"
                       ":name)")
    old = find(ctx, task.name)
    if old is not None:
        if old["state"] in ("WORKING", "PAUSED"):
            rt.tasks.cancel(old["id"])
        rt.tasks.delete(old["id"])
    made = rt.tasks.create(task.tree, name=task.name, owner=OWNER, kind=KIND,
                           blackboard={MAP_KEY: snap.map or ""},
                           start=task.mode == convert.IMMEDIATE)
    nexts = [rt.tasks.schedules.create(made["id"], spec)["next_fire"]
             for spec in task.schedules]
    log.info("puwei: task %s set (mode %d, %d schedules)", task.name, task.mode, len(nexts))
    return {"name": task.name, "id": made["id"], "mode": task.mode, "schedules": nexts}


@ROUTES.get("/api/task/run/:name")
def run_task(ctx: Context, request: PuweiRequest) -> dict[str, Any]:
    """Run stored task ``name`` now (from its start). ``data``: ``{"name", "id"}``."""
    name = request.name()
    task = find(ctx, name)
    if task is None:
        raise NotFound("task", name)
    if ctx.runtime.status().mode != "navigating":
        raise Conflict("a task needs navigation (GET /api/roslaunch/navigation/:name)")
    ctx.runtime.tasks.start(task["id"])
    return {"name": name, "id": task["id"]}


@ROUTES.get("/api/scheduler/release")
def release(ctx: Context, request: PuweiRequest) -> int:
    """Drop the schedules of the tasks set on map ``map``. ``data``: how many were dropped."""
    map_name = request.query.get("map", "")
    if not map_name.strip():
        raise InvalidRequest("map", "the query parameter map is required")
    site_store(ctx).map_record(map_name)  # NotFound first
    rt = ctx.runtime
    dropped = 0
    for task in rt.tasks.list(owner=OWNER, kind=KIND):
        if task["blackboard"].get(MAP_KEY) != map_name:
            continue
        for schedule in rt.tasks.schedules.list(task["id"]):
            rt.tasks.schedules.delete(schedule["id"])
            dropped += 1
    log.info("puwei: %d schedules of map %s released", dropped, map_name)
    return dropped
