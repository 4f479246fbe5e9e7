"""The simulated 2-D lidar: ray casting into the ground truth, people as circles, range noise.

Beams start at ``angle_min = -fov / 2``. A full circle spaces them ``2π / beams`` apart over
[-π, π) (the beam at +π would repeat the one at -π); a narrower field of view puts the first and
last beam on its edges, ``fov / (beams - 1)`` apart. Walls come from
:func:`polynav.maps.raycast.cast_rays`; each person adds the nearer intersection of the beam with
its circle. Each return then gets independent Gaussian noise. A return beyond ``range_max`` or
nearer than ``range_min`` (after noise) is reported as ``inf``: no valid echo, as ROS drivers
mark out-of-range readings.
"""

from __future__ import annotations

import functools
import logging
import math

import numba
import numpy as np
import numpy.typing as npt

from polynav.geometry import Pose2D
from polynav.maps.map import MapInfo
from polynav.maps.raycast import cast_rays
from polynav.robot.interface import LaserScan
from polynav.robot.sim.charger import segment_ranges
from polynav.robot.sim.config import SimConfig

log = logging.getLogger(__name__)


class Lidar:
    """A lidar mounted on the base at ``(lidar_x, lidar_y, lidar_theta)`` of the config (the
    centre, looking along the heading, by default); its scans carry the mount as
    ``sensor_pose``."""

    def __init__(self, config: SimConfig, rng: np.random.Generator) -> None:
        self._config = config
        self._rng = rng
        n = config.lidar_beams
        full_circle = config.lidar_fov >= 2.0 * math.pi - 1e-12
        self.angle_min = -0.5 * config.lidar_fov
        if n == 1:
            self.angle_min, self.angle_increment = 0.0, 0.0
        elif full_circle:
            self.angle_increment = config.lidar_fov / n
        else:
            self.angle_increment = config.lidar_fov / (n - 1)
        self._angles = self.angle_min + self.angle_increment * np.arange(n, dtype=np.float64)
        self._mount = Pose2D(config.lidar_x, config.lidar_y, config.lidar_theta)
        warm_up()

    def scan(
        self,
        occupied: npt.NDArray[np.bool_],
        info: MapInfo,
        pose: Pose2D,
        people: npt.NDArray[np.float64],
        stamp: float,
        segments: npt.NDArray[np.float64] | None = None,
    ) -> LaserScan:
        """One sweep from ``pose`` (true, world frame).

        Args:
            occupied: ground truth ``[iy, ix]``, C-contiguous.
            info: where the grid sits.
            pose: the robot's true pose.
            people: (K, 3) rows of person x, y, radius [m] on this floor.
            stamp: time of the sweep [s].
            segments: (S, 4) rows ``x0, y0, x1, y1`` of thin bodies cast exactly (the
                chargers' plates, :mod:`~polynav.robot.sim.charger`).
        """
        c = self._config
        sensor = pose.compose(self._mount)
        world = self._angles + sensor.theta
        ranges = cast_rays(occupied, info, sensor.x, sensor.y, world, c.lidar_range)
        if people.shape[0]:
            ranges = np.minimum(ranges, circle_ranges(sensor.x, sensor.y, world, people,
                                                      c.lidar_range))
        if segments is not None and segments.shape[0]:
            ranges = np.minimum(ranges, segment_ranges(sensor.x, sensor.y, world, segments,
                                                       c.lidar_range))
        if c.lidar_range_noise > 0.0:
            ranges = ranges + c.lidar_range_noise * self._rng.standard_normal(ranges.shape[0])
        ranges[(ranges > c.lidar_range) | (ranges < c.lidar_range_min)] = np.inf
        return LaserScan(
            stamp=stamp,
            angle_min=self.angle_min,
            angle_increment=self.angle_increment,
            range_min=c.lidar_range_min,
            range_max=c.lidar_range,
            ranges=ranges.astype(np.float32),
            sensor_pose=self._mount,
        )


def circle_ranges(
    x: float,
    y: float,
    angles: npt.NDArray[np.float64],
    circles: npt.NDArray[np.float64],
    max_range: float,
) -> npt.NDArray[np.float64]:
    """Distance [m] from (x, y) along each world angle [rad] to the first circle it enters.

    Solves ``|p + t u - c|² = r²`` for the smaller root ``t > 0`` per beam and circle; ``inf``
    where a beam misses every circle within ``max_range``, or starts inside one.
    """
    out = np.full(angles.shape[0], np.inf)
    if circles.shape[0]:
        _circle_ranges(float(x), float(y), np.cos(angles), np.sin(angles),
                       np.ascontiguousarray(circles, dtype=np.float64), float(max_range), out)
    return out


@numba.njit(cache=True, nogil=True)
def _circle_ranges(
    x: float,
    y: float,
    ux: npt.NDArray[np.float64],
    uy: npt.NDArray[np.float64],
    circles: npt.NDArray[np.float64],
    max_range: float,
    out: npt.NDArray[np.float64],
) -> None:
    """:func:`circle_ranges` over beam directions (ux, uy), lowering ``out`` in place: one pass
    per scan instead of a dozen array operations per person."""
    for c in range(circles.shape[0]):
        dx, dy, r = circles[c, 0] - x, circles[c, 1] - y, circles[c, 2]
        dist2 = dx * dx + dy * dy
        if dist2 <= r * r or math.sqrt(dist2) - r > max_range:
            continue
        for k in range(ux.shape[0]):
            along = ux[k] * dx + uy[k] * dy
            disc = along * along - (dist2 - r * r)
            if disc >= 0.0 and along > 0.0:
                out[k] = min(out[k], along - math.sqrt(disc))


@functools.cache
def warm_up() -> None:
    """Compile (or load from numba's cache) the people kernel, once per process: a lidar calls
    it when built, so the first scan with someone in view is not late by a compile."""
    circle_ranges(0.0, 0.0, np.zeros(2), np.array([[1.0, 0.0, 0.3]]), 10.0)
