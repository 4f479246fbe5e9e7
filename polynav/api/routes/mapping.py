"""/api/mapping: build a new map while the robot is driven, watch it grow, save it, stop, cancel."""

from __future__ import annotations

import logging

from fastapi import APIRouter
from fastapi.responses import Response

from polynav.api.deps import RuntimeDep
from polynav.api.errors import BODY, LOOKUP, STATE, responses
from polynav.api.schemas import GridOut, MapOut, MappingStartIn, MapSaveIn, Ok
from polynav.maps.ros_map import png_bytes

log = logging.getLogger(__name__)

router = APIRouter(prefix="/api/mapping", tags=["mapping"], responses=STATE)


@router.post("/start", operation_id="start_mapping", response_model=Ok,
             responses=responses(BODY, LOOKUP))
def start_mapping(runtime: RuntimeDep, body: MappingStartIn | None = None) -> Ok:
    """Start a new map where the robot stands (no body; 409 unless free: stop navigation
    first), or update ``map``: extend it in its own frame, the robot localized on it at
    ``point``, at the pose, by navigation when navigating on it, or by global relocalization
    (409 ``not_localized`` when not found; 404 unknown map or point). Drive the robot with
    teleop or exploration meanwhile; the status shows its pose on the map being built. An
    updated map may be saved under its own name without ``overwrite``."""
    if body is None or body.map is None:
        runtime.start_mapping()
    else:
        runtime.start_mapping(body.map, point=body.point, pose=body.pose())
    return Ok()


@router.post("/explore", operation_id="explore", response_model=Ok)
def explore(runtime: RuntimeDep) -> Ok:
    """Let the robot map on its own: frontier after frontier of the live map, then back to
    where it began (event ``exploration_finished``); 409 unless mapping, or already exploring.
    Teleop takes over while it is given."""
    runtime.explore()
    return Ok()


@router.get("/map", operation_id="get_mapping_map", response_model=GridOut)
def get_mapping_map(runtime: RuntimeDep) -> GridOut:
    """The map built so far as a grid: ``data`` row by row from the bottom row (``iy = 0``),
    100 occupied, 0 free, -1 unknown (409 unless mapping)."""
    return GridOut.from_domain(runtime.mapping_map())


@router.get(
    "/map.png",
    operation_id="get_mapping_map_image",
    response_class=Response,
    responses={200: {"content": {"image/png": {}}}},
)
def get_mapping_map_image(runtime: RuntimeDep) -> Response:
    """The map built so far as the ROS PNG (row 0 at the top; 409 unless mapping)."""
    return Response(png_bytes(runtime.mapping_map()), media_type="image/png")


@router.post("/save", operation_id="save_mapping", response_model=MapOut,
             responses=responses(BODY))
def save_mapping(body: MapSaveIn, runtime: RuntimeDep) -> MapOut:
    """Save the map so far under ``name``; mapping goes on (409 if the name is taken and
    ``overwrite`` is not set, or unless mapping)."""
    runtime.save_mapping(body.name, overwrite=body.overwrite)
    return MapOut.from_domain(runtime.store.map_record(body.name))


@router.post("/stop", operation_id="stop_mapping", response_model=MapOut,
             responses=responses(BODY))
def stop_mapping(body: MapSaveIn, runtime: RuntimeDep) -> MapOut:
    """Finish the map, save it under ``name`` and become free (409 as for save)."""
    runtime.stop_mapping(body.name, overwrite=body.overwrite)
    return MapOut.from_domain(runtime.store.map_record(body.name))


@router.post("/cancel", operation_id="cancel_mapping", response_model=Ok)
def cancel_mapping(runtime: RuntimeDep) -> Ok:
    """Drop the map being built and become free (409 unless mapping)."""
    runtime.cancel_mapping()
    return Ok()
