"""A route across maps: the legs the robot runs in order.

A :class:`Route` alternates in-map drives with crossings: a :class:`DriveLeg` is one goal on one
map (planned and followed by the navigator), a :class:`LiftLeg` is the lift sequence from the
outside point of one floor to the outside point of another (DESIGN §4, ``docs/lifts.md``), a
:class:`SwitchLeg` changes maps at a direct connection (the same place on two maps).
"""

from __future__ import annotations

from dataclasses import dataclass

from polynav.geometry import Pose2D


@dataclass(frozen=True, slots=True)
class DriveLeg:
    """Drive to ``goal`` (the point ``point``, if named) on ``map_name``."""

    map_name: str
    goal: Pose2D
    point: str | None = None

    @property
    def kind(self) -> str:
        return "drive"


@dataclass(frozen=True, slots=True)
class LiftLeg:
    """Ride car ``car`` from ``from_floor`` to ``to_floor``: the robot stands at ``outside_from``
    (on ``from_map``) when the leg starts and at ``outside_to`` (on ``to_map``) when it ends.

    Attributes:
        waiting_from: where to wait for the car's session on the first floor (``None``: at the
            outside point).
    """

    car: str
    from_floor: str
    from_map: str
    to_floor: str
    to_map: str
    outside_from: Pose2D
    inside_from: Pose2D
    outside_to: Pose2D
    inside_to: Pose2D
    waiting_from: Pose2D | None = None
    outside_point: str = ""
    inside_point: str = ""

    @property
    def kind(self) -> str:
        return "lift"


@dataclass(frozen=True, slots=True)
class SwitchLeg:
    """Change from ``from_map`` to ``to_map`` at a direct connection: the robot stands at
    ``from_pose`` and is at ``to_pose`` on the new map (the same place)."""

    from_map: str
    to_map: str
    from_pose: Pose2D
    to_pose: Pose2D
    to_point: str = ""

    @property
    def kind(self) -> str:
        return "switch"


Leg = DriveLeg | LiftLeg | SwitchLeg


@dataclass(frozen=True, slots=True)
class Route:
    """The legs in order and the expected duration [s] the router weighed them at."""

    legs: tuple[Leg, ...]
    cost: float

    @property
    def cars(self) -> tuple[str, ...]:
        return tuple(leg.car for leg in self.legs if isinstance(leg, LiftLeg))
