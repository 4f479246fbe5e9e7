"""A simulated people (leg) detector: what a lidar leg tracker reports about nearby people.

Only people the lidar can actually see are reported: within its range and field of view, with
the line from the sensor to the person free of walls (people do not hide each other: a leg
tracker sees legs between legs). Each person keeps a track id while they stay visible; one who
disappears and comes back gets a new id, as with a real tracker. Positions and velocities are
in the robot frame (+x forward, +y left); the velocity is the person's own motion (estimated from
successive observations), turned into the robot's axes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from polynav.geometry import Pose2D
from polynav.maps.map import MapInfo
from polynav.robot.interface import PersonDetection


@dataclass(slots=True)
class _Track:
    track_id: int
    stamp: float
    x: float  # map frame
    y: float
    vx: float = 0.0
    vy: float = 0.0


class PeopleDetector:
    """Detects people from ground truth as a leg tracker on the robot's lidar would."""

    def __init__(self, max_range: float, fov: float) -> None:
        self._max_range = max_range
        self._fov = fov
        self._tracks: dict[int, _Track] = {}
        self._next_id = 0

    def detect(
        self,
        stamp: float,
        robot: Pose2D,
        people: list[tuple[float, float]],
        occupied: npt.NDArray[np.bool_],
        info: MapInfo,
    ) -> list[PersonDetection]:
        """The people (map-frame positions, by index) visible from ``robot`` at ``stamp``."""
        seen: dict[int, _Track] = {}
        for index, (px, py) in enumerate(people):
            if not self._visible(robot, px, py, occupied, info):
                continue
            track = self._tracks.get(index)
            if track is None:
                track = _Track(self._next_id, stamp, px, py)
                self._next_id += 1
            else:
                dt = stamp - track.stamp
                if dt > 1e-6:
                    track.vx, track.vy = (px - track.x) / dt, (py - track.y) / dt
                    track.stamp, track.x, track.y = stamp, px, py
            seen[index] = track
        self._tracks = seen
        c, s = math.cos(robot.theta), math.sin(robot.theta)
        out = []
        for track in sorted(seen.values(), key=lambda t: t.track_id):
            dx, dy = track.x - robot.x, track.y - robot.y
            out.append(PersonDetection(
                track.track_id,
                c * dx + s * dy,
                -s * dx + c * dy,
                c * track.vx + s * track.vy,
                -s * track.vx + c * track.vy,
            ))
        return out

    def _visible(
        self,
        robot: Pose2D,
        px: float,
        py: float,
        occupied: npt.NDArray[np.bool_],
        info: MapInfo,
    ) -> bool:
        dx, dy = px - robot.x, py - robot.y
        distance = math.hypot(dx, dy)
        if distance > self._max_range:
            return False
        bearing = math.atan2(dy, dx) - robot.theta
        bearing = math.atan2(math.sin(bearing), math.cos(bearing))
        if self._fov < 2.0 * math.pi and abs(bearing) > 0.5 * self._fov:
            return False
        steps = max(2, int(distance / (0.5 * info.resolution)))
        t = np.linspace(0.0, 1.0, steps)
        xs = np.floor((robot.x + t * dx - info.origin.x) / info.resolution).astype(np.int64)
        ys = np.floor((robot.y + t * dy - info.origin.y) / info.resolution).astype(np.int64)
        inside = (xs >= 0) & (ys >= 0) & (xs < info.width) & (ys < info.height)
        return not bool(np.any(occupied[ys[inside], xs[inside]]))
