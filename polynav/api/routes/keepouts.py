"""/api/maps/{name}/keepouts: the virtual walls and forbidden zones drawn on a map.

A map's keepouts are one ordered list: GET reads it, POST appends one shape, PUT replaces the
whole list (the console's undo writes back the list it read before its edit). An edit of the
map navigated on applies at once: the running plan and the next ones avoid the new shapes.
The shapes routes with stops mirror into the list (:mod:`polynav.store.route_stops`) are
listed like any other.
"""

from __future__ import annotations

import logging

from fastapi import APIRouter, Body

from polynav.api.deps import MapNamePath, RuntimeDep, StoreDep
from polynav.api.errors import BODY, LOOKUP, STATE, responses
from polynav.api.examples import examples
from polynav.api.schemas_console import (
    MAX_KEEPOUTS,
    KeepoutIO,
    KeepoutList,
    keepout_from_domain,
    keepout_to_domain,
)
from polynav.errors import Conflict
from polynav.runtime.robot_runtime import RobotRuntime

log = logging.getLogger(__name__)

router = APIRouter(prefix="/api/maps", tags=["maps"], responses=LOOKUP)

# On the demo's floor1: a wall across the hall west of the lobby, a zone in its corner.
_WALL = {"kind": "wall", "points": [[2.0, 11.0], [2.0, 13.0]], "thickness": 0.05}
_ZONE = {"kind": "zone", "polygon": [[0.5, 15.5], [1.5, 15.5], [1.5, 16.5], [0.5, 16.5]]}
OneBody = Body(openapi_examples=examples(virtual_wall=_WALL, forbidden_zone=_ZONE))
ListBody = Body(openapi_examples=examples(wall_and_zone=[_WALL, _ZONE], none=[]))


def _apply(runtime: RobotRuntime, map_name: str) -> None:
    """Make navigation on ``map_name`` use the edited keepouts now."""
    if runtime.map_name == map_name:
        runtime.reload_keepouts()


@router.get("/{name}/keepouts", operation_id="list_keepouts", response_model=list[KeepoutIO])
def list_keepouts(name: MapNamePath, store: StoreDep) -> list[KeepoutIO]:
    """The map's walls and zones, in the order they were drawn (404 unknown map)."""
    return [keepout_from_domain(k) for k in store.keepouts(name)]


@router.put("/{name}/keepouts", operation_id="replace_keepouts",
            response_model=list[KeepoutIO], responses=responses(BODY, STATE))
def replace_keepouts(name: MapNamePath, store: StoreDep, runtime: RuntimeDep,
                     body: KeepoutList = ListBody) -> list[KeepoutIO]:
    """Replace all the map's walls and zones at once (an empty list clears them)."""
    shapes = [keepout_to_domain(k) for k in body]
    stored = store.set_keepouts(name, shapes)
    _apply(runtime, name)
    return [keepout_from_domain(k) for k in stored]


@router.post("/{name}/keepouts", operation_id="add_keepout", response_model=list[KeepoutIO],
             status_code=201, responses=responses(BODY, STATE))
def add_keepout(name: MapNamePath, store: StoreDep, runtime: RuntimeDep,
                body: KeepoutIO = OneBody) -> list[KeepoutIO]:
    """Draw one more wall or zone on the map; answers with the whole list (409 when the map
    already has the most keepouts one map may have)."""
    shape = keepout_to_domain(body)
    current = store.keepouts(name)
    if len(current) >= MAX_KEEPOUTS:
        raise Conflict(f"map {name!r} already has {MAX_KEEPOUTS} keepouts")
    stored = store.set_keepouts(name, [*current, shape])
    _apply(runtime, name)
    return [keepout_from_domain(k) for k in stored]
