"""The site's named points: list, add, change, delete.

Point names are unique per map, not per site (the demo has ``initial`` on both floors), so the
routes that name one take ``?map=`` to say which when the name alone is ambiguous (409 otherwise).
"""

from __future__ import annotations

import logging

from fastapi import APIRouter, Response

from polynav.api.deps import FloorFilter, MapFilter, MapOfPoint, PointNamePath, StoreDep
from polynav.api.errors import BODY, LOOKUP, STATE, responses
from polynav.api.schemas import PointIn, PointOut, PointUpdate
from polynav.store.site_store import SiteStore

log = logging.getLogger(__name__)

# Every route names a map or a point (404, 422); beyond the listing, an ambiguous or a taken name
# is a 409.
router = APIRouter(prefix="/api/points", tags=["points"], responses=LOOKUP)


def _floors_by_map(store: SiteStore) -> dict[str, str]:
    return {floor.map_name: floor.name for floor in store.floors()}


@router.get("", operation_id="list_points", response_model=list[PointOut])
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
    responses=responses(BODY, STATE),
)
def create_point(body: PointIn, store: StoreDep) -> PointOut:
    """Add a point (409 if the map already has one of that name, 404 if the map is unknown)."""
    point = store.add_point(body.to_domain())
    return PointOut.from_domain(point, _floors_by_map(store).get(point.map_name))


@router.get("/{name}", operation_id="get_point", response_model=PointOut, responses=STATE)
def get_point(name: PointNamePath, store: StoreDep, map: MapOfPoint = None) -> PointOut:  # noqa: A002
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
    name: PointNamePath, body: PointUpdate, store: StoreDep, map: MapOfPoint = None  # noqa: A002
) -> PointOut:
    """Change a point: the fields given replace the old ones; ``name`` renames it."""
    old = store.find_point(name, map_name=map)
    point = store.update_point(old.map_name, old.name, body.to_domain(old))
    return PointOut.from_domain(point, _floors_by_map(store).get(point.map_name))


@router.delete("/{name}", operation_id="delete_point", status_code=204, responses=STATE)
def delete_point(
    name: PointNamePath, store: StoreDep, map: MapOfPoint = None  # noqa: A002
) -> Response:
    """Delete a point."""
    point = store.find_point(name, map_name=map)
    store.delete_point(point.map_name, point.name)
    return Response(status_code=204)
