"""Runtime events of cross-map routes and the lift sequence, for every dialect.

A goal on another map is one attempt to its callers (one ``navigation_started``, one
``navigation_succeeded`` or ``navigation_failed``), made of legs: these events say what happens
inside it. Dialects map them once (Yunji: ``running_status`` lift values and the 040xx
notifications).
"""

from __future__ import annotations

import enum
from dataclasses import dataclass
from typing import ClassVar

from polynav.runtime.events import RuntimeEvent


class LiftPhase(enum.Enum):
    """Where a route's lift sequence stands (the status's ``lift.phase``)."""

    GOING_TO_LIFT = "going_to_lift"
    WAITING_FOR_SESSION = "waiting_for_session"
    CALLING = "calling"
    WAITING_FOR_CAR = "waiting_for_car"
    ENTERING = "entering"
    RIDING = "riding"
    SWITCHING_MAP = "switching_map"
    EXITING = "exiting"
    LEFT = "left"


HELD = "held by another robot"
"""``detail`` of a ``waiting_for_session`` event sent when the session is not granted at once."""


@dataclass(frozen=True, slots=True)
class RouteStarted(RuntimeEvent):
    """A goal on another map was routed: its legs (``drive``, ``lift``, ``switch``) and cars."""

    kind: ClassVar[str] = "route_started"

    attempt_id: int
    legs: tuple[str, ...]
    cars: tuple[str, ...]


@dataclass(frozen=True, slots=True)
class LiftPhaseChanged(RuntimeEvent):
    """The lift sequence of attempt ``attempt_id`` entered ``phase`` with car ``car``, going
    from ``from_floor`` to ``to_floor``; ``detail`` says why for a retry or a change of car."""

    kind: ClassVar[str] = "lift_phase"

    attempt_id: int
    car: str
    phase: LiftPhase
    from_floor: str
    to_floor: str
    detail: str = ""


@dataclass(frozen=True, slots=True)
class MapSwitched(RuntimeEvent):
    """Navigation goes on on ``to_map`` (floor ``floor``): the robot left the lift or crossed a
    direct connection; localization restarted at ``pose``'s place."""

    kind: ClassVar[str] = "map_switched"

    attempt_id: int
    from_map: str
    to_map: str
    floor: str
