"""Where the robot is in the building: its floor, and what naming a map, point or pose does to it.

The runtime asks the same questions of every backend (which floor is the robot on, which floor
is a map on, "the operator says the robot is here"), and the answers differ:

* :class:`SimulatedPlacement`: the simulator knows the truth. The site map of a floor shares
  the world floor's frame (the store seeds it from the world), so a map leads to a floor of the
  world and a pose on that map is a pose on that floor. "Start navigation" on a map of another
  floor lifts the simulated robot there, and an initial pose far from where it stands puts it
  there, as an operator would carry a robot to where they say it is.
* :class:`ReportedPlacement`: a real robot (driven over rosbridge) cannot be carried by
  software. Its floor is the one the operator or a lift ride last said, its pose only what
  localization estimates; naming a pose records the floor and moves nothing.
"""

from __future__ import annotations

import logging
from collections.abc import Mapping, Sequence
from typing import Protocol

from polynav.errors import InvalidRequest
from polynav.geometry import Pose2D
from polynav.robot.door import Door
from polynav.robot.lift import Lift
from polynav.robot.sim.simulation import Simulation
from polynav.site import Point, PointKind

log = logging.getLogger(__name__)

# An initial pose farther than this from the truth is taken as "the operator carried the robot
# there" (localization relocalizes only within ~1 m / 30°).
PLACE_DISTANCE = 1.0
PLACE_ANGLE = 0.5


class FloorsAndPoints(Protocol):
    """The part of the site store placement reads."""

    def floors(self) -> Sequence[object]: ...

    def points(
        self, *, map_name: str | None = None, floor: str | None = None
    ) -> Sequence[Point]: ...


class Placement(Protocol):
    """The robot's place in the building, as the runtime reads and sets it."""

    @property
    def name(self) -> str:
        """The robot's name (lift sessions and the fleet know it by it)."""
        ...

    @property
    def floor(self) -> str:
        """The floor the robot is on."""
        ...

    @property
    def lifts(self) -> Mapping[str, Lift]:
        """The building's lift cars this robot can call, by name."""
        ...

    @property
    def doors(self) -> Mapping[str, Door]:
        """The building's electronic doors and gates this robot can open, by name."""
        ...

    def true_pose(self) -> Pose2D | None:
        """Where the robot really stands, when the backend knows (the simulator)."""
        ...

    def floor_of(self, store: FloorsAndPoints, map_name: str, floor: object) -> str:
        """The floor map ``map_name`` (recorded on ``floor``) lies on.

        Raises:
            InvalidRequest: the map is on no floor the robot can be on.
        """
        ...

    def place(self, floor: str, pose: Pose2D) -> None:
        """The operator (or a ride) says the robot stands at ``pose`` on ``floor``.

        Raises:
            InvalidRequest: the pose cannot be (in a wall of the simulated world).
        """
        ...


def initial_point(store: FloorsAndPoints, map_name: str) -> Pose2D | None:
    """The pose of the map's initial point, ``None`` when it has none."""
    for p in store.points(map_name=map_name):
        if p.kind is PointKind.INITIAL:
            return p.pose
    return None


def _recorded_floor(store: FloorsAndPoints, map_name: str, floor: object,
                    names: set[str] | None) -> str | None:
    if isinstance(floor, str) and (names is None or floor in names):
        return floor
    for record in store.floors():
        name = getattr(record, "name", None)
        if getattr(record, "map_name", None) == map_name and isinstance(name, str) and (
                names is None or name in names):
            return name
    return None


class SimulatedPlacement:
    """The simulator's truth (see the module docstring)."""

    def __init__(self, sim: Simulation) -> None:
        self._sim = sim

    @property
    def name(self) -> str:
        return self._sim.name

    @property
    def floor(self) -> str:
        return self._sim.floor

    @property
    def lifts(self) -> Mapping[str, Lift]:
        return self._sim.scene.lifts

    @property
    def doors(self) -> Mapping[str, Door]:
        return self._sim.scene.doors

    def true_pose(self) -> Pose2D | None:
        return self._sim.true_pose

    def floor_of(self, store: FloorsAndPoints, map_name: str, floor: object) -> str:
        found = _recorded_floor(store, map_name, floor, {f.name for f in self._sim.world.floors})
        if found is None:
            raise InvalidRequest("map", f"map {map_name!r} is on no floor of the simulated world")
        return found

    def place(self, floor: str, pose: Pose2D) -> None:
        sim = self._sim
        true = sim.true_pose
        if (
            sim.floor != floor
            or true.distance_to(pose) > PLACE_DISTANCE
            or abs(true.heading_error_to(pose)) > PLACE_ANGLE
        ):
            sim.teleport(floor, pose)


class ReportedPlacement:
    """A real robot's place: what the operator and the rides report (see the module docstring).

    Args:
        name: the robot's name.
        floor: the floor it is on at start (the site's first floor when the runtime makes it).
    """

    def __init__(self, name: str, floor: str) -> None:
        self._name = name
        self._floor = floor

    @property
    def name(self) -> str:
        return self._name

    @property
    def floor(self) -> str:
        return self._floor

    @property
    def lifts(self) -> Mapping[str, Lift]:
        return {}  # a real site's lift controllers are not wired to a bridged robot yet

    @property
    def doors(self) -> Mapping[str, Door]:
        return {}  # nor its door controllers

    def true_pose(self) -> Pose2D | None:
        return None

    def floor_of(self, store: FloorsAndPoints, map_name: str, floor: object) -> str:
        found = _recorded_floor(store, map_name, floor, None)
        return found if found is not None else map_name  # a map of no floor is a floor of its own

    def place(self, floor: str, pose: Pose2D) -> None:
        if floor != self._floor:
            log.info("the robot is on floor %s now (was %s)", floor, self._floor)
        self._floor = floor
