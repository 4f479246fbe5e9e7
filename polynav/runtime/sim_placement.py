"""Where the simulated robot stands when the operator names a map, a point or a pose.

On the simulator the site map of a floor shares the world floor's frame (the store seeds it
from the world), so a map leads to a floor of the world and a pose on that map is a pose on that
floor. "Start navigation" on a map of another floor lifts the simulated robot there (there is no
lift ride yet), and an initial pose far from where the simulated robot stands puts it there, as
an operator would carry a robot to where they say it is.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from typing import Protocol

from polynav.errors import InvalidRequest
from polynav.geometry import Pose2D
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


def floor_of(sim: Simulation, store: FloorsAndPoints, map_name: str, floor: object) -> str:
    """The simulated world's floor that map ``map_name`` (recorded on ``floor``) lies on.

    Raises:
        InvalidRequest: the map is on no floor of the simulated world.
    """
    names = {f.name for f in sim.world.floors}
    if isinstance(floor, str) and floor in names:
        return floor
    for record in store.floors():
        name = getattr(record, "name", None)
        if getattr(record, "map_name", None) == map_name and name in names:
            return str(name)
    raise InvalidRequest("map", f"map {map_name!r} is on no floor of the simulated world")


def initial_point(store: FloorsAndPoints, map_name: str) -> Pose2D | None:
    """The pose of the map's initial point, ``None`` when it has none."""
    for p in store.points(map_name=map_name):
        if p.kind is PointKind.INITIAL:
            return p.pose
    return None


def place(sim: Simulation, floor: str, pose: Pose2D) -> None:
    """Put the simulated robot where the operator says it is, if it is not near there.

    Raises:
        InvalidRequest: the pose lies in a wall (from the simulator).
    """
    true = sim.true_pose
    if (
        sim.floor != floor
        or true.distance_to(pose) > PLACE_DISTANCE
        or abs(true.heading_error_to(pose)) > PLACE_ANGLE
    ):
        sim.teleport(floor, pose)
