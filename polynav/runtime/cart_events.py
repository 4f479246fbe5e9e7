"""Runtime events of carts and cabins: docking to one, leaving it, for every dialect.

One :class:`CartAction` event per change: a dock or a leave ``started``, ``retried`` (with the
reason of the failed try), ``succeeded`` or ``failed`` (with its reason). Dialects map them
once (Yunji: ``running_status`` ``dock_to_container`` ... and the 0105x-0108x notices).
"""

from __future__ import annotations

import enum
from dataclasses import dataclass
from typing import ClassVar

from polynav.runtime.events import RuntimeEvent


class CartStep(enum.Enum):
    """What happened to a dock or a leave."""

    STARTED = "started"
    RETRIED = "retried"
    SUCCEEDED = "succeeded"
    FAILED = "failed"


class CartFailure(enum.Enum):
    """Why a dock or a leave failed (``reason`` of a ``failed`` or ``retried`` event)."""

    NOT_REACHED = "not_reached"  # the way to the cart's entry failed
    NOT_SEEN = "not_seen"  # no legs where the cart should stand
    NOT_ALIGNED = "not_aligned"  # in, but not within the tolerance of the cart's centre
    WRONG_CABIN = "wrong_cabin"  # the latch's tag reader read another cabin's id
    NOT_TAKEN = "not_taken"  # the jack or latch did not take the load
    NOT_RELEASED = "not_released"  # the jack or latch did not let go
    BLOCKED = "blocked"  # the way out from under the load is blocked
    CANCELED = "canceled"


@dataclass(frozen=True, slots=True)
class CartAction(RuntimeEvent):
    """A dock to (``action`` ``dock``) or a leave of (``leave``) cart or cabin ``cart`` (its
    ``load`` kind: ``cart`` or ``cabin``) changed: ``step``, and for a failure or a retry its
    ``reason`` and ``detail``; ``attempt`` counts the tries from 1."""

    kind: ClassVar[str] = "cart_action"

    action: str
    cart: str
    load: str
    step: CartStep
    attempt: int = 1
    reason: CartFailure | None = None
    detail: str = ""
