"""The building's lift cars: their state, an operator's request, and (simulator) their mode.

Robots use the cars on their own (a goal on another map); these routes are for people: see
where each car is, call one for maintenance (taking its session, so robots wait), and on the
simulator put one out of service to rehearse a breakdown.
"""

from __future__ import annotations

import logging

from fastapi import APIRouter

from polynav.api.deps import RuntimeDep
from polynav.api.errors import BODY, LOOKUP, STATE, responses
from polynav.api.schemas import Ok
from polynav.api.schemas_lifts import LiftModeIn, LiftOut, LiftRequestIn, LiftsOut
from polynav.errors import InvalidRequest

log = logging.getLogger(__name__)

router = APIRouter(prefix="/api/lifts", tags=["lifts"])


@router.get("", operation_id="list_lifts", response_model=LiftsOut,
            summary="Every lift car of the building")
def list_lifts(runtime: RuntimeDep) -> LiftsOut:
    """Each car: floors served, where it is, doors, motion, mode, session owner, riders."""
    return LiftsOut(lifts=[LiftOut.from_domain(lift.state())
                           for _, lift in sorted(runtime.lifts.items())])


@router.post("/{car}/request", operation_id="request_lift", response_model=LiftOut,
             responses=responses(BODY, LOOKUP, STATE))
def request_lift(car: str, body: LiftRequestIn, runtime: RuntimeDep) -> LiftOut:
    """Send the car to ``floor`` (doors ``open`` or ``closed``) in the ``session``, or end it
    (404 no such car; 409 a floor it does not serve, out of service, another session)."""
    if not body.end_session and body.floor is None:
        raise InvalidRequest("floor", "give the floor to go to, or end_session")
    runtime.request_lift(car, body.to_domain())
    return LiftOut.from_domain(runtime.lift(car).state())


@router.post("/{car}/mode", operation_id="set_lift_mode", response_model=Ok,
             responses=responses(BODY, LOOKUP, STATE))
def set_lift_mode(car: str, body: LiftModeIn, runtime: RuntimeDep) -> Ok:
    """Put the simulated car in or out of service (404 no such car)."""
    runtime.set_lift_mode(car, body.to_domain())
    return Ok()
