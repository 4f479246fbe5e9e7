"""The site's named points: list, add, change, delete.

Point names are unique per map, not per site (the demo has ``initial`` on both floors), so the
routes that name one take ``?map=`` to say which when the name alone is ambiguous (409 otherwise).
"""

from __future__ import annotations

import logging
from typing import Annotated

from fastapi import APIRouter, Body, Path, Response

from polynav.api.deps import FloorFilter, MapFilter, MapOfPoint, StoreDep
from polynav.api.errors import BODY, LOOKUP, STATE, responses
from polynav.api.examples import (
    DEMO_MAP,
    GOAL_POINT,
    MOVED_POINT,
    NEW_POINT,
    REMOVED_POINT,
    examples,
    link,
    links,
    one,
)
from polynav.api.schemas import Name, PointIn, PointOut, PointUpdate
from polynav.store.site_store import SiteStore

log = logging.getLogger(__name__)

# Every route names a map or a point (404, 422); beyond the listing, an ambiguous or a taken name
# is a 409.
router = APIRouter(prefix="/api/points", tags=["points"], responses=LOOKUP)

# Each route its own example point, so that the delete's does not take the one the read names.
ReadName = Annotated[Name, Path(description="the point's name",
                                openapi_examples=one("a demo point", GOAL_POINT))]
MovedName = Annotated[Name, Path(description="the point's name",
                                 openapi_examples=one("a demo point", MOVED_POINT))]
RemovedName = Annotated[Name, Path(description="the point's name",
                                   openapi_examples=one("a demo point", REMOVED_POINT))]
NewPoint = Annotated[PointIn, Body(openapi_examples=examples(
    a_point_by_the_lobby={"name": NEW_POINT, "map": DEMO_MAP, "x": 6.0, "y": 11.0,
                          "theta": 0.0, "kind": "general"},
))]
PointChange = Annotated[PointUpdate, Body(openapi_examples=examples(
    move_it={"x": 31.0, "y": 20.5}, turn_it={"theta": 0.0},
))]
# A point, listed or made, can be read by its name, and is where navigation can start: the robot
# localized at it.
LISTED = links(
    ReadListedPoint=link(
        "get_point", parameters={"name": "$response.body#/0/name", "map": "$response.body#/0/map"},
        description="read the first point by its name and map"),
    StartNavigationAtListedPoint=link(
        "start_navigation",
        body={"map": "$response.body#/0/map", "point": "$response.body#/0/name"},
        description="navigate on the first point's map, localized at it"))
CREATED = links(
    ReadCreatedPoint=link(
        "get_point", parameters={"name": "$response.body#/name", "map": "$response.body#/map"},
        description="read the point back by its name and map"),
    StartNavigationAtCreatedPoint=link(
        "start_navigation", body={"map": "$response.body#/map", "point": "$response.body#/name"},
        description="navigate on the point's map, localized at it"))


def _floors_by_map(store: SiteStore) -> dict[str, str]:
    return {floor.map_name: floor.name for floor in store.floors()}


@router.get("", operation_id="list_points", response_model=list[PointOut],
            responses={200: LISTED})
def list_points(
    store: StoreDep, map: MapFilter = None, floor: FloorFilter = None  # noqa: A002
) -> list[PointOut]:
    """The named points, optionally of one map or floor (404 if that map or floor is unknown)."""
    floors = _floors_by_map(store)
    points = store.points(map_name=map, floor=floor)
    return [PointOut.from_domain(p, floors.get(p.map_name)) for p in points]


@router.post(
    "",
    operation_id="create_point",
    response_model=PointOut,
    status_code=201,
    responses=responses(BODY, STATE, {201: CREATED}),
)
def create_point(body: NewPoint, store: StoreDep) -> PointOut:
    """Add a point (409 if the map already has one of that name, 404 if the map is unknown)."""
    point = store.add_point(body.to_domain())
    return PointOut.from_domain(point, _floors_by_map(store).get(point.map_name))


@router.get("/{name}", operation_id="get_point", response_model=PointOut, responses=STATE)
def get_point(name: ReadName, store: StoreDep, map: MapOfPoint = None) -> PointOut:  # noqa: A002
    """One point by name."""
    point = store.find_point(name, map_name=map)
    return PointOut.from_domain(point, _floors_by_map(store).get(point.map_name))


@router.put(
    "/{name}",
    operation_id="update_point",
    response_model=PointOut,
    responses=responses(BODY, STATE),
)
def update_point(
    name: MovedName, body: PointChange, store: StoreDep, map: MapOfPoint = None  # noqa: A002
) -> PointOut:
    """Change a point: the fields given replace the old ones; ``name`` renames it."""
    old = store.find_point(name, map_name=map)
    point = store.update_point(old.map_name, old.name, body.to_domain(old))
    return PointOut.from_domain(point, _floors_by_map(store).get(point.map_name))


@router.delete("/{name}", operation_id="delete_point", status_code=204, responses=STATE)
def delete_point(
    name: RemovedName, store: StoreDep, map: MapOfPoint = None  # noqa: A002
) -> Response:
    """Delete a point."""
    point = store.find_point(name, map_name=map)
    store.delete_point(point.map_name, point.name)
    return Response(status_code=204)
