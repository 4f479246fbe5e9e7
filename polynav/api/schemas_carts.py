"""Pydantic models of the cart routes (``/api/carts``: the loads, dock, leave)."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field

from polynav.worlds.carts import WorldCart


class CartOut(BaseModel):
    """One cart or cabin of the building, where the robot believes it stands."""

    name: str
    kind: Literal["cart", "cabin"]
    floor: str
    x: float
    y: float
    theta: float = Field(description="the way a docked robot faces [rad]")
    length: float = Field(description="between its front and back legs' centres [m]")
    width: float = Field(description="between its left and right legs' centres [m]")
    mass: float = Field(description="[kg]")
    carried: bool = Field(description="whether this robot carries it")

    @classmethod
    def from_domain(cls, cart: WorldCart, floor: str, x: float, y: float, theta: float,
                    carried: bool) -> CartOut:
        return cls(name=cart.name, kind=cart.kind.value, floor=floor, x=x, y=y, theta=theta,
                   length=cart.length, width=cart.width, mass=cart.mass, carried=carried)


class LoadOut(BaseModel):
    """What the robot carries."""

    name: str
    kind: Literal["cart", "cabin"]
    mass: float


class CartActionOut(BaseModel):
    """A dock or leave under way: the load, its phase and try."""

    action: Literal["dock", "leave"]
    cart: str
    load: Literal["cart", "cabin"]
    phase: Literal["going", "seeing", "entering", "taking", "carrying", "releasing", "exiting"]
    attempt: int


class CartsOut(BaseModel):
    """GET /api/carts: the loads, what the robot carries and what it is doing with them."""

    carts: list[CartOut]
    load: LoadOut | None
    action: CartActionOut | None


class DockIn(BaseModel):
    """Dock to a cart or cabin: by its ``cart`` name or the ``point`` of the current map it
    stands at (exactly one); a cabin's ``cabin_id`` is checked against its tag when given."""

    model_config = ConfigDict(extra="forbid")

    cart: str | None = Field(default=None, min_length=1, max_length=200)
    point: str | None = Field(default=None, min_length=1, max_length=200)
    cabin_id: str | None = Field(default=None, min_length=1, max_length=200)


class LeaveIn(BaseModel):
    """Leave the load: carried to ``point`` (on ``map``, default the current map) first when
    one is given, else where the robot stands."""

    model_config = ConfigDict(extra="forbid")

    point: str | None = Field(default=None, min_length=1, max_length=200)
    map: str | None = Field(default=None, min_length=1, max_length=200)
