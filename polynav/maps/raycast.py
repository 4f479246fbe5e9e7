"""Ray casting through an occupancy grid: the one kernel behind the simulated lidar and any
scan-expectation model.

The traversal is Amanatides & Woo's voxel walk ("A Fast Voxel Traversal Algorithm for Ray
Tracing", Eurographics 1987): it visits exactly the cells a ray crosses, so thin walls are never
skipped however long the ray. The map origin must have zero yaw, as every ROS map does in practice.
"""

from __future__ import annotations

import math

import numba
import numpy as np
import numpy.typing as npt

from polynav.maps.map import MapInfo


@numba.njit(cache=True, nogil=True)
def _cast(
    occupied: npt.NDArray[np.bool_],
    origin_x: float,
    origin_y: float,
    resolution: float,
    x: float,
    y: float,
    angles: npt.NDArray[np.float64],
    max_range: float,
    out: npt.NDArray[np.float64],
) -> None:
    height, width = occupied.shape
    gx = (x - origin_x) / resolution
    gy = (y - origin_y) / resolution
    max_cells = max_range / resolution
    for k in range(angles.shape[0]):
        dx = math.cos(angles[k])
        dy = math.sin(angles[k])
        ix = int(math.floor(gx))
        iy = int(math.floor(gy))
        step_x = 1 if dx > 0.0 else -1
        step_y = 1 if dy > 0.0 else -1
        if dx != 0.0:
            t_delta_x = abs(1.0 / dx)
            next_x = (ix + 1.0 - gx) if dx > 0.0 else (gx - ix)
            t_max_x = next_x * t_delta_x
        else:
            t_delta_x = math.inf
            t_max_x = math.inf
        if dy != 0.0:
            t_delta_y = abs(1.0 / dy)
            next_y = (iy + 1.0 - gy) if dy > 0.0 else (gy - iy)
            t_max_y = next_y * t_delta_y
        else:
            t_delta_y = math.inf
            t_max_y = math.inf
        hit = math.inf
        t = 0.0
        while t <= max_cells:
            if ix < 0 or iy < 0 or ix >= width or iy >= height:
                break
            if occupied[iy, ix]:
                hit = t * resolution
                break
            if t_max_x < t_max_y:
                t = t_max_x
                t_max_x += t_delta_x
                ix += step_x
            else:
                t = t_max_y
                t_max_y += t_delta_y
                iy += step_y
        out[k] = hit if hit <= max_range else math.inf


def cast_rays(
    occupied: npt.NDArray[np.bool_],
    info: MapInfo,
    x: float,
    y: float,
    angles: npt.NDArray[np.float64],
    max_range: float,
) -> npt.NDArray[np.float64]:
    """Distance [m] from (x, y) along each world-frame angle [rad] to the first occupied cell.

    Args:
        occupied: boolean grid ``[iy, ix]``, ``True`` where a ray stops.
        info: where the grid sits; its origin yaw must be 0.
        x, y: ray start [m], world frame.
        angles: ray directions [rad], world frame.
        max_range: longest distance reported [m].

    Returns:
        One distance per angle; ``inf`` where nothing is hit within ``max_range`` or the ray
        leaves the grid. A ray starting inside an occupied cell returns 0.
    """
    if info.origin.theta != 0.0:
        raise ValueError("cast_rays needs a map origin with zero yaw")
    a = np.ascontiguousarray(angles, dtype=np.float64)
    out = np.empty(a.shape[0], dtype=np.float64)
    _cast(
        np.ascontiguousarray(occupied, dtype=np.bool_),
        info.origin.x,
        info.origin.y,
        info.resolution,
        float(x),
        float(y),
        a,
        float(max_range),
        out,
    )
    return out
