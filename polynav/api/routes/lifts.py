"""The building's lift cars: their state, an operator's request, and (simulator) their mode.

Robots use the cars on their own (a goal on another map); these routes are for people: see
where each car is, call one for maintenance (taking its session, so robots wait), and on the
simulator put one out of service to rehearse a breakdown.
"""

from __future__ import annotations

import logging
from typing import Annotated

from fastapi import APIRouter, Body, Path

from polynav.api.deps import RuntimeDep
from polynav.api.errors import BODY, LOOKUP, STATE, responses
from polynav.api.examples import DEMO_CAR, DEMO_CAR_FLOOR, examples, link, links, one
from polynav.api.schemas import Ok
from polynav.api.schemas_lifts import LiftModeIn, LiftOut, LiftRequestIn, LiftsOut
from polynav.errors import InvalidRequest

log = logging.getLogger(__name__)

router = APIRouter(prefix="/api/lifts", tags=["lifts"])

Car = Annotated[str, Path(description="the car's name (GET /api/lifts)",
                          openapi_examples=one("a demo car", DEMO_CAR))]
RequestBody = Annotated[LiftRequestIn, Body(openapi_examples=examples(
    go_to_a_floor={"floor": DEMO_CAR_FLOOR, "door": "open"},
    end_the_session={"end_session": True},
))]
ModeBody = Annotated[LiftModeIn, Body(openapi_examples=examples(
    back_in_service={"mode": "normal"}, out_of_service={"mode": "out_of_service"},
))]
# A listed car leads to its request and mode: the first car, to the second floor it serves.
_FIRST_CAR = "$response.body#/lifts/0/name"
LISTED_CARS = links(
    RequestListedCar=link("request_lift", parameters={"car": _FIRST_CAR},
                          body={"floor": "$response.body#/lifts/0/floors/1"},
                          description="call the first car to a floor it serves"),
    SetListedCarMode=link("set_lift_mode", parameters={"car": _FIRST_CAR},
                          description="put the first car in or out of service"),
)


@router.get("", operation_id="list_lifts", response_model=LiftsOut,
            summary="Every lift car of the building", responses={200: LISTED_CARS})
def list_lifts(runtime: RuntimeDep) -> LiftsOut:
    """Each car: floors served, where it is, doors, motion, mode, session owner, riders."""
    return LiftsOut(lifts=[LiftOut.from_domain(lift.state())
                           for _, lift in sorted(runtime.lifts.items())])


@router.post("/{car}/request", operation_id="request_lift", response_model=LiftOut,
             responses=responses(BODY, LOOKUP, STATE))
def request_lift(car: Car, body: RequestBody, runtime: RuntimeDep) -> LiftOut:
    """Send the car to ``floor`` (doors ``open`` or ``closed``) in the ``session``, or end it
    (404 no such car; 409 a floor it does not serve, out of service, another session)."""
    if not body.end_session and body.floor is None:
        raise InvalidRequest("floor", "give the floor to go to, or end_session")
    runtime.request_lift(car, body.to_domain())
    return LiftOut.from_domain(runtime.lift(car).state())


@router.post("/{car}/mode", operation_id="set_lift_mode", response_model=Ok,
             responses=responses(BODY, LOOKUP, STATE))
def set_lift_mode(car: Car, body: ModeBody, runtime: RuntimeDep) -> Ok:
    """Put the simulated car in or out of service (404 no such car)."""
    runtime.set_lift_mode(car, body.to_domain())
    return Ok()
