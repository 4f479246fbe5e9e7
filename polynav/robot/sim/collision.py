"""Contact between the robot's disk and the world: ground-truth walls, people, other robots.

Clearance is the gap [m] between the robot's edge and the nearest obstacle, negative when they
overlap. Against walls it is exact for the grid: each occupied cell is the full square it covers,
and the distance is from the disk's centre to the nearest point of that square. Cells beyond the
grid's edge count as occupied, since the world ends there. People are circles.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass
from typing import Literal

import numba
import numpy as np
import numpy.typing as npt

from polynav.geometry import Pose2D
from polynav.maps.map import MapInfo

log = logging.getLogger(__name__)

Obstacle = Literal["wall", "person", "robot"]


@dataclass(frozen=True, slots=True)
class Collision:
    """The robot touched an obstacle: when [s], where (true pose), and what."""

    stamp: float
    pose: Pose2D
    obstacle: Obstacle


@numba.njit(cache=True, nogil=True)
def _wall_clearance(
    occupied: npt.NDArray[np.bool_],
    origin_x: float,
    origin_y: float,
    resolution: float,
    x: float,
    y: float,
    radius: float,
    horizon: float,
) -> float:
    height, width = occupied.shape
    reach = radius + horizon
    gx = (x - origin_x) / resolution
    gy = (y - origin_y) / resolution
    ix0 = int(math.floor(gx - reach / resolution))
    ix1 = int(math.floor(gx + reach / resolution))
    iy0 = int(math.floor(gy - reach / resolution))
    iy1 = int(math.floor(gy + reach / resolution))
    best = reach
    for iy in range(iy0, iy1 + 1):
        # Distance along y from the centre to the cell's square, 0 if within its rows.
        cy0 = origin_y + iy * resolution
        dy = max(cy0 - y, 0.0, y - (cy0 + resolution))
        if dy >= best:
            continue
        for ix in range(ix0, ix1 + 1):
            if 0 <= ix < width and 0 <= iy < height and not occupied[iy, ix]:
                continue
            cx0 = origin_x + ix * resolution
            dx = max(cx0 - x, 0.0, x - (cx0 + resolution))
            d = math.sqrt(dx * dx + dy * dy)
            if d < best:
                best = d
    if best >= reach:
        return horizon  # exactly: reach - radius would round below it
    return best - radius


def wall_clearance(
    occupied: npt.NDArray[np.bool_],
    info: MapInfo,
    x: float,
    y: float,
    *,
    radius: float,
    horizon: float,
) -> float:
    """Gap [m] between a disk at (x, y) and the nearest occupied cell, up to ``horizon``.

    Args:
        occupied: ground truth ``[iy, ix]``, C-contiguous.
        info: where the grid sits; its origin yaw must be 0.
        x, y: disk centre [m], world frame.
        radius: disk radius [m].
        horizon: farthest gap worth measuring [m]; a larger gap is reported as ``horizon``.

    Returns:
        The gap, negative on overlap (``-radius`` when the centre is inside a wall).
    """
    return float(_wall_clearance(occupied, info.origin.x, info.origin.y, info.resolution,
                                 float(x), float(y), float(radius), float(horizon)))


def person_clearance(
    x: float, y: float, radius: float, people: npt.NDArray[np.float64]
) -> float:
    """Gap [m] between a disk at (x, y) and the nearest person; ``inf`` with no people.

    Args:
        x, y, radius: the disk [m].
        people: (K, 3) rows of person x, y, radius [m].
    """
    if people.shape[0] == 0:
        return math.inf
    gaps = np.hypot(people[:, 0] - x, people[:, 1] - y) - people[:, 2] - radius
    return float(gaps.min())


def warm_up() -> None:
    """Compile the kernel on a tiny grid (the runtime calls this at start-up)."""
    grid = np.zeros((3, 3), dtype=np.bool_)
    grid[1, 1] = True
    _wall_clearance(grid, 0.0, 0.0, 1.0, 0.5, 0.5, 0.25, 0.1)
