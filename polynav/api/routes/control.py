"""Direct control of the base: teleop velocity, software e-stop, local moves."""

from __future__ import annotations

import logging

from fastapi import APIRouter

from polynav.api.deps import RuntimeDep
from polynav.api.errors import BODY, STATE, responses
from polynav.api.schemas import EStopIn, LocalMoveIn, Ok, TeleopIn

log = logging.getLogger(__name__)

router = APIRouter(prefix="/api", tags=["control"], responses=responses(BODY, STATE))


@router.post("/teleop", operation_id="teleop", response_model=Ok)
def teleop(body: TeleopIn, runtime: RuntimeDep) -> Ok:
    """Drive at a velocity; without a new command within the dead-man timeout the base stops
    (409 while a goal runs)."""
    runtime.teleop(body.linear, body.angular)
    return Ok()


@router.post("/estop", operation_id="set_estop", response_model=Ok)
def set_estop(body: EStopIn, runtime: RuntimeDep) -> Ok:
    """Press or release the software emergency stop."""
    runtime.set_software_estop(body.on)
    return Ok()


@router.post("/local_move", operation_id="local_move", response_model=Ok)
def local_move(body: LocalMoveIn, runtime: RuntimeDep) -> Ok:
    """Rotate by ``rotate`` [rad] or drive ``distance`` [m] straight, checked against obstacles
    (409 while a goal runs)."""
    runtime.local_move(rotate=body.rotate, distance=body.distance)
    return Ok()
