"""A simulated people (leg) detector: what a lidar leg tracker reports about nearby people.

Only people the lidar can actually see are reported: within its range and field of view, with
the line from the sensor to the person free of walls (people do not hide each other: a leg
tracker sees legs between legs). Each person keeps a track id while they stay visible; one who
disappears and comes back gets a new id, as with a real tracker. Positions and velocities are
in the robot frame (+x forward, +y left); the velocity is the person's own motion (estimated from
successive observations), turned into the robot's axes.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numba
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
        warm_up()

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
        return not _sight_blocked(occupied, _fractions(steps), robot.x, robot.y, dx, dy,
                                  info.origin.x, info.origin.y, info.resolution)


@functools.lru_cache(maxsize=4096)
def _fractions(steps: int) -> npt.NDArray[np.float64]:
    """``np.linspace(0, 1, steps)``, read-only: the sight line's samples, made once per length
    instead of on every check."""
    t = np.linspace(0.0, 1.0, steps)
    t.flags.writeable = False
    return t


@numba.njit(cache=True, nogil=True)
def _sight_blocked(
    occupied: npt.NDArray[np.bool_],
    t: npt.NDArray[np.float64],
    x: float,
    y: float,
    dx: float,
    dy: float,
    origin_x: float,
    origin_y: float,
    resolution: float,
) -> bool:
    """Whether a cell on the grid holding a sample ``(x, y) + t (dx, dy)`` is occupied.

    Each cell index is ``floor((x + t dx - origin) / resolution)``, operation by operation as
    the array expression it replaced computed it (no fused or reordered arithmetic), so it
    picks the same cells; cells off the grid are skipped.
    """
    height, width = occupied.shape
    for k in range(t.shape[0]):
        ix = int(math.floor((x + t[k] * dx - origin_x) / resolution))
        iy = int(math.floor((y + t[k] * dy - origin_y) / resolution))
        if 0 <= ix < width and 0 <= iy < height and occupied[iy, ix]:
            return True
    return False


@functools.cache
def warm_up() -> None:
    """Compile (or load from numba's cache) the sight-line kernel, once per process: a detector
    calls it when built, so the first check is not late by a compile."""
    _sight_blocked(np.zeros((1, 1), dtype=np.bool_), _fractions(2), 0.0, 0.0, 0.0, 0.0, 0.0,
                   0.0, 1.0)
