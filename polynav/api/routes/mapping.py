"""/api/mapping: build a new map while the robot is driven, watch it grow, save it, stop, cancel."""

from __future__ import annotations

import logging
from typing import Annotated

from fastapi import APIRouter, Body, Path
from fastapi.responses import Response

from polynav.api.deps import RuntimeDep
from polynav.api.errors import BODY, LOOKUP, STATE, responses
from polynav.api.examples import DEMO_MAP, NEW_MAP, START_POINT, examples
from polynav.api.schemas import GridOut, MappingStartIn, MapSaveIn, Ok
from polynav.api.schemas_mapping import MappingJobOut
from polynav.maps.ros_map import png_bytes

log = logging.getLogger(__name__)

router = APIRouter()
commands = APIRouter(prefix="/api/mapping", tags=["mapping"], responses=STATE)
jobs = APIRouter(prefix="/api/mapping/jobs", tags=["mapping"])  # a read: no 409

JobId = Annotated[str, Path(min_length=1, max_length=200, description="the job's id")]
StartBody = Annotated[MappingStartIn | None, Body(openapi_examples=examples(
    a_new_map={},
    extend_a_map_from_a_point={"map": DEMO_MAP, "point": START_POINT},
    extend_a_map_from_a_pose={"map": DEMO_MAP, "x": 8.0, "y": 8.5, "theta": 0.0},
))]
SaveBody = Annotated[MapSaveIn, Body(openapi_examples=examples(
    under_a_new_name={"name": NEW_MAP},
))]


@commands.post("/start", operation_id="start_mapping", response_model=Ok,
             responses=responses(BODY, LOOKUP))
def start_mapping(runtime: RuntimeDep, body: StartBody = None) -> Ok:
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


@commands.post("/explore", operation_id="explore", response_model=Ok)
def explore(runtime: RuntimeDep) -> Ok:
    """Let the robot map on its own: frontier after frontier of the live map, then back to
    where it began (event ``exploration_finished``); 409 unless mapping, or already exploring.
    Teleop takes over while it is given."""
    runtime.explore()
    return Ok()


@commands.get("/map", operation_id="get_mapping_map", response_model=GridOut)
def get_mapping_map(runtime: RuntimeDep) -> GridOut:
    """The map built so far as a grid: ``data`` row by row from the bottom row (``iy = 0``),
    100 occupied, 0 free, -1 unknown (409 unless mapping)."""
    return GridOut.from_domain(runtime.mapping_map())


@commands.get(
    "/map.png",
    operation_id="get_mapping_map_image",
    response_class=Response,
    responses={200: {"content": {"image/png": {}}}},
)
def get_mapping_map_image(runtime: RuntimeDep) -> Response:
    """The map built so far as the ROS PNG (row 0 at the top; 409 unless mapping)."""
    return Response(png_bytes(runtime.mapping_map()), media_type="image/png")


@commands.post("/save", operation_id="save_mapping", response_model=MappingJobOut,
             status_code=202, responses=responses(BODY))
def save_mapping(body: SaveBody, runtime: RuntimeDep) -> MappingJobOut:
    """Save the map so far under ``name``; mapping goes on. Answers at once with the job
    (``saving``): the files are written off the robot's control loop, the status's
    ``mapping.job`` and ``GET /api/mapping/jobs/{id}`` follow it to ``saved`` (the map is then
    in ``GET /api/maps``) or ``failed`` (``error``: the disk, the store). 409 at once if the
    name is taken and ``overwrite`` is not set, unless mapping, or while another save runs."""
    return MappingJobOut.from_domain(
        runtime.save_mapping_job(body.name, overwrite=body.overwrite))


@commands.post("/stop", operation_id="stop_mapping", response_model=MappingJobOut,
             status_code=202, responses=responses(BODY))
def stop_mapping(body: SaveBody, runtime: RuntimeDep) -> MappingJobOut:
    """Finish the map (its last optimisation), save it under ``name`` and become free.
    Answers at once with the job (``saving``), always 202: the finish runs off the robot's
    control loop, the robot ``busy`` (halted) meanwhile, the status's ``mapping`` showing the
    session and its job; when ``saved`` the robot is ``free`` and the map in
    ``GET /api/maps``; when ``failed`` it is ``mapping`` again, nothing lost. 409 at once as
    for save, and while a stop runs."""
    return MappingJobOut.from_domain(
        runtime.stop_mapping_job(body.name, overwrite=body.overwrite))


@commands.post("/cancel", operation_id="cancel_mapping", response_model=Ok)
def cancel_mapping(runtime: RuntimeDep) -> Ok:
    """Drop the map being built and become free (409 unless mapping)."""
    runtime.cancel_mapping()
    return Ok()


@jobs.get("/{job_id}", operation_id="get_mapping_job", response_model=MappingJobOut,
          responses=LOOKUP)
def get_mapping_job(job_id: JobId, runtime: RuntimeDep) -> MappingJobOut:
    """A save job of the map being built (``saving``, ``saved``, ``failed``); 404 for an
    unknown id (the last 32 jobs are kept)."""
    return MappingJobOut.from_domain(runtime.mapping_job(job_id))


router.include_router(commands)
router.include_router(jobs)
