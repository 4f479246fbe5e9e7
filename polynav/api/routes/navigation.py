"""Navigation on a map: start/stop, initial pose, goals, cancel/pause/resume."""

from __future__ import annotations

import logging
from typing import Annotated

from fastapi import APIRouter, Body

from polynav.api.deps import RuntimeDep
from polynav.api.errors import BODY, LOOKUP, STATE, responses
from polynav.api.examples import DEMO_MAP, GOAL_POINT, START_POINT, examples, link, links
from polynav.api.schemas import GoalAccepted, GoalIn, NavigationStartIn, Ok, PoseIn

log = logging.getLogger(__name__)

router = APIRouter(prefix="/api/navigation", tags=["navigation"], responses=STATE)

StartBody = Annotated[NavigationStartIn, Body(openapi_examples=examples(
    at_a_named_point={"map": DEMO_MAP, "point": START_POINT},
    at_a_pose={"map": DEMO_MAP, "x": 8.0, "y": 8.5, "theta": 0.0},
))]
InitialPoseBody = Annotated[PoseIn, Body(openapi_examples=examples(
    where_the_demo_robot_starts={"x": 8.0, "y": 8.5, "theta": 0.0},
))]
GoalBody = Annotated[GoalIn, Body(openapi_examples=examples(
    to_a_named_point={"point": GOAL_POINT},
    to_a_pose={"x": 13.5, "y": 12.4, "theta": 0.0},
    a_metre_ahead={"x": 1.0, "y": 0.0, "theta": 0.0, "frame": "robot"},
))]
# Navigation started at a point leads to a goal at it (the robot is there: it arrives at once).
STARTED = links(GoalAtTheStart=link(
    "send_goal", body={"point": "$request.body#/point"},
    description="a goal at the point navigation started at"))


@router.post(
    "/start",
    operation_id="start_navigation",
    response_model=Ok,
    responses=responses(BODY, LOOKUP, {200: STARTED}),
)
def start_navigation(body: StartBody, runtime: RuntimeDep) -> Ok:
    """Load a map and navigate on it, localized at ``point``, at the pose, or where the simulated
    robot stands (404 unknown map or point, 409 while mapping)."""
    runtime.start_navigation(body.map, point=body.point, pose=body.pose())
    return Ok()


@router.post("/stop", operation_id="stop_navigation", response_model=Ok)
def stop_navigation(runtime: RuntimeDep) -> Ok:
    """Cancel any goal and leave navigation mode."""
    runtime.stop_navigation()
    return Ok()


@router.post(
    "/initial_pose", operation_id="set_initial_pose", response_model=Ok, responses=BODY
)
def set_initial_pose(body: InitialPoseBody, runtime: RuntimeDep) -> Ok:
    """Tell the localizer where the robot is (409 unless navigating)."""
    runtime.set_initial_pose(body.to_domain())
    return Ok()


@router.post(
    "/goal",
    operation_id="send_goal",
    response_model=GoalAccepted,
    status_code=202,
    responses=responses(BODY, LOOKUP),
)
def send_goal(body: GoalBody, runtime: RuntimeDep) -> GoalAccepted:
    """Go to a named point or a pose; answers at once with the attempt id, progress comes in
    the status and the events (404 unknown point, 409 unless navigating or for a frame that is
    not the current one). A pose with ``"frame": "robot"`` is relative to where the robot
    stands now. ``precise`` (or ``max_position_uncertainty``) fails the goal ``not localized``
    rather than succeed where localization cannot confirm the pose."""
    attempt = runtime.go_to(point=body.point, pose=body.pose(), map_name=body.map,
                            options=body.options(), frame=body.goal_frame())
    return GoalAccepted(id=int(attempt))


@router.post("/cancel", operation_id="cancel_goal", response_model=Ok)
def cancel_goal(runtime: RuntimeDep) -> Ok:
    """Cancel the running or paused goal (409 if none)."""
    runtime.cancel()
    return Ok()


@router.post("/pause", operation_id="pause_goal", response_model=Ok)
def pause_goal(runtime: RuntimeDep) -> Ok:
    """Stop in place, keeping the goal (409 if none runs)."""
    runtime.pause()
    return Ok()


@router.post("/resume", operation_id="resume_goal", response_model=Ok)
def resume_goal(runtime: RuntimeDep) -> Ok:
    """Go on to the paused goal (409 if none is paused)."""
    runtime.resume()
    return Ok()
