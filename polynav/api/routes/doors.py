"""The building's electronic doors and gates: their state, and an operator's hand on one.

Robots open the doors on their way themselves; these routes are for people: see each door, hold
one open by hand (a delivery, a drill) and let it go again. A robot's hold and the operator's
are apart: letting go by hand never closes a door on a robot that holds it.
"""

from __future__ import annotations

import logging

from fastapi import APIRouter

from polynav.api.deps import RuntimeDep
from polynav.api.errors import LOOKUP, responses
from polynav.api.schemas_doors import DoorOut, DoorsOut

log = logging.getLogger(__name__)

router = APIRouter(prefix="/api/doors", tags=["doors"])


@router.get("", operation_id="list_doors", response_model=DoorsOut,
            summary="Every door and gate of the building")
def list_doors(runtime: RuntimeDep) -> DoorsOut:
    """Each door: kind, floor, place, state, who holds it open, whether it answers."""
    return DoorsOut(doors=[DoorOut.from_domain(s) for s in runtime.door_states()])


@router.post("/{door}/open", operation_id="open_door", response_model=DoorOut,
             responses=responses(LOOKUP), summary="Hold a door open by hand")
def open_door(door: str, runtime: RuntimeDep) -> DoorOut:
    """Hold the door open as the operator until it is closed by hand (404 no such door)."""
    return DoorOut.from_domain(runtime.open_door(door))


@router.post("/{door}/close", operation_id="close_door", response_model=DoorOut,
             responses=responses(LOOKUP), summary="Let go of a door by hand")
def close_door(door: str, runtime: RuntimeDep) -> DoorOut:
    """The operator lets go: the door closes unless a robot holds it (404 no such door)."""
    return DoorOut.from_domain(runtime.close_door(door))
