"""GET /api/maps, /api/maps/{name}, /api/maps/{name}/image.png: the site's maps."""

from __future__ import annotations

import logging

from fastapi import APIRouter
from fastapi.responses import FileResponse

from polynav.api.deps import MapNamePath, StoreDep
from polynav.api.errors import LOOKUP
from polynav.api.schemas import MapOut

log = logging.getLogger(__name__)

router = APIRouter(prefix="/api/maps", tags=["maps"])


@router.get("", operation_id="list_maps", response_model=list[MapOut])
def list_maps(store: StoreDep) -> list[MapOut]:
    """Every map of the site, with its geometry."""
    return [MapOut.from_domain(record) for record in store.maps()]


@router.get("/{name}", operation_id="get_map", response_model=MapOut, responses=LOOKUP)
def get_map(name: MapNamePath, store: StoreDep) -> MapOut:
    """One map's metadata (404 if unknown)."""
    return MapOut.from_domain(store.map_record(name))


@router.get(
    "/{name}/image.png",
    operation_id="get_map_image",
    response_class=FileResponse,
    responses={200: {"content": {"image/png": {}}}, **LOOKUP},
)
def get_map_image(name: MapNamePath, store: StoreDep) -> FileResponse:
    """The map as the ROS PNG (row 0 at the top, as image viewers expect)."""
    return FileResponse(store.map_image_path(name), media_type="image/png")
