"""Carts and cabins: the loads of the building, and the robot docking to, carrying and leaving
them (:mod:`polynav.runtime.cart_commands`).

A dock or a leave runs on its own; its progress is ``GET /api/carts`` (``action``) and the
``cart_action`` events of the event stream (started, retried, succeeded, failed with a reason
such as ``wrong_cabin``). A request the robot cannot honour (nothing to dock to, a load heavier
than it carries, carrying one already) is refused at once with nothing changed (409).
"""

from __future__ import annotations

import logging
from typing import Annotated, Any

from fastapi import APIRouter, Body

from polynav.api.deps import RuntimeDep
from polynav.api.errors import BODY, LOOKUP, STATE, responses
from polynav.api.examples import examples
from polynav.api.schemas_carts import (
    CartActionOut,
    CartOut,
    CartsOut,
    DockIn,
    LeaveIn,
    LoadOut,
)
from polynav.runtime.robot_runtime import RobotRuntime

log = logging.getLogger(__name__)

router = APIRouter(prefix="/api/carts", tags=["carts"])

DockBody = Annotated[DockIn, Body(openapi_examples=examples(
    a_cart_by_name={"cart": "cart_1"},
    a_cabin_checking_its_id={"cart": "cabin_1", "cabin_id": "CAB-0001"},
))]
LeaveBody = Annotated[LeaveIn, Body(openapi_examples=examples(
    where_it_stands={},
    at_a_point_on_another_floor={"point": "initial", "map": "floor2"},
))]


def _carts(runtime: RobotRuntime) -> CartsOut:
    service = runtime.carts
    load = service.load
    out = []
    for cart in service.loads():
        floor, pose = service.where(cart)
        carried = load is not None and load.cart.name == cart.name
        if load is not None and carried and runtime.is_simulated:
            sim_cart = runtime.simulation.scene.carts.carts[cart.name]
            floor, pose = sim_cart.floor, runtime.status().pose.compose(load.offset)
        out.append(CartOut.from_domain(cart, floor, pose.x, pose.y, pose.theta, carried))
    status: dict[str, Any] = service.status()
    return CartsOut(carts=out,
                    load=None if status["load"] is None else LoadOut(**status["load"]),
                    action=None if status["action"] is None
                    else CartActionOut(**status["action"]))


@router.get("", operation_id="list_carts", response_model=CartsOut,
            summary="The carts and cabins, and what the robot carries")
def list_carts(runtime: RuntimeDep) -> CartsOut:
    """Each load where the robot believes it stands, the robot's load and its dock or leave
    under way."""
    return _carts(runtime)


@router.post("/dock", operation_id="dock_cart", response_model=CartsOut,
             responses=responses(BODY, LOOKUP, STATE),
             summary="Dock to a cart or cabin (lift or latch it)")
def dock_cart(body: DockBody, runtime: RuntimeDep) -> CartsOut:
    """Go to the load, find it by its legs, drive in and lift (a cart) or latch (a cabin). 409:
    not navigating, nothing to dock to, a load heavier than the robot carries, busy; 404: an
    unknown point."""
    runtime.carts.dock(cart=body.cart, point=body.point, cabin_id=body.cabin_id)
    return _carts(runtime)


@router.post("/leave", operation_id="leave_cart", response_model=CartsOut,
             responses=responses(BODY, LOOKUP, STATE),
             summary="Leave the load (at a point, or where the robot stands)")
def leave_cart(body: LeaveBody, runtime: RuntimeDep) -> CartsOut:
    """Carry the load to the point first if one is given, then lower the jack (or open the
    latch) and drive out from under it. 409: nothing carried, busy; 404: an unknown point."""
    runtime.carts.leave(point=body.point, map_name=body.map)
    return _carts(runtime)


@router.post("/cancel", operation_id="cancel_cart_action", response_model=CartsOut,
             summary="Stop a dock or leave under way")
def cancel_cart_action(runtime: RuntimeDep) -> CartsOut:
    """The robot halts where it is; the dock or leave fails ``canceled``."""
    runtime.carts.cancel()
    return _carts(runtime)
