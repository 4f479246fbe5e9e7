"""Carts and cabins on the task engine: ``dock_cart_action`` and ``leave_cart_action``
(polynav's own types, over :mod:`polynav.runtime.cart_commands`).

``dock_cart_action`` docks to the cart or cabin named ``cart``, or to the one standing at
``point`` of the current map; a cabin's tag must read ``cabin_id`` when one is given. It is done
(``COMPLETE``) when the load is lifted or latched; a dock that fails after its retries (not
seen, not aligned, a wrong cabin id) is ``FAIL`` with the reason; one refused at the start
(nothing to dock to, too heavy, carrying already) is ``ERROR``. ``leave_cart_action`` carries the
load to ``point`` (on ``map``) first when one is given, then leaves it and drives out; ``FAIL``
after its retries. Cancelling either stops the robot where it is.

Blackboard, once it ended: ``cart.name`` (the load docked to or left).
"""

from __future__ import annotations

from typing import Any

from pydantic import Field, model_validator

from polynav.tasks.action import Action, Params, action_type
from polynav.tasks.node import Run
from polynav.tasks.states import NodeState


class DockCartParams(Params):
    cart: str | None = Field(default=None, min_length=1)
    point: str | None = Field(default=None, min_length=1)
    cabin_id: str | None = Field(default=None, min_length=1)

    @model_validator(mode="after")
    def _one_target(self) -> DockCartParams:
        if (self.cart is None) == (self.point is None):
            raise ValueError("give exactly one of cart and point")
        return self


class LeaveCartParams(Params):
    point: str | None = Field(default=None, min_length=1)
    map: str | None = Field(default=None, min_length=1)


class _CartAction(Action):
    """One dock or leave, followed by its number."""

    writes = ("cart.name",)

    def __init__(self, params: dict[str, Any], **kwargs: Any) -> None:
        super().__init__(params, **kwargs)
        self.number: int | None = None

    def poll(self, run: Run) -> NodeState | None:
        assert self.number is not None
        outcome = run.robot.cart_outcome(self.number)
        if outcome is None:
            return None
        succeeded, cart, detail = outcome
        run.blackboard.write("cart.name", cart)
        if succeeded:
            return NodeState.COMPLETE
        self.result = detail
        return NodeState.FAIL

    def halt(self, run: Run) -> None:
        run.robot.cancel_cart()

    def reset(self) -> None:
        super().reset()
        self.number = None

    def live(self) -> dict[str, Any]:
        return {"number": self.number}


@action_type
class DockCartAction(_CartAction):
    """Dock to a cart (lift it) or a cabin (latch it)."""

    type = "dock_cart_action"
    schema = DockCartParams

    def begin(self, run: Run) -> None:
        p = self.p
        assert isinstance(p, DockCartParams)
        self.number = run.robot.dock_cart(cart=p.cart, point=p.point, cabin_id=p.cabin_id)


@action_type
class LeaveCartAction(_CartAction):
    """Leave the load carried (at a point first, when one is given)."""

    type = "leave_cart_action"
    schema = LeaveCartParams

    def begin(self, run: Run) -> None:
        p = self.p
        assert isinstance(p, LeaveCartParams)
        self.number = run.robot.leave_cart(point=p.point, map_name=p.map)
