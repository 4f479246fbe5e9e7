"""Contact between the robot's body and the world: ground-truth walls and people.

Clearance is the gap [m] between the robot's edge and the nearest obstacle, negative when they
overlap. Against walls it is exact for the grid: each occupied cell is the full square it covers,
and the distance is from the disk's centre to the nearest point of that square. Cells beyond the
grid's edge count as occupied, since the world ends there. People are circles.

A body may be a polygon (a rectangular base, :attr:`SimConfig.footprint_polygon`). Its gap to a
wall is the exact distance between the polygon and the nearest occupied square; when they
overlap, the negative value is how deep the deepest square reaches into the body (the largest
distance from a point of the square inside the polygon to the polygon's edge, sampled at the
square's corners, centre and the polygon's vertices inside the square). Only the sign and whether
the overlap deepens matter to the simulator, which refuses a move that starts or deepens one.
People keep to the disk that holds the body (its circumscribed radius), as they give a rectangle
the berth of its corners.
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

Obstacle = Literal["wall", "person"]


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


@numba.njit(cache=True, nogil=True)
def _segment_distance(px: float, py: float, ax: float, ay: float, bx: float, by: float) -> float:
    dx, dy = bx - ax, by - ay
    length2 = dx * dx + dy * dy
    t = 0.0
    if length2 > 0.0:
        t = min(1.0, max(0.0, ((px - ax) * dx + (py - ay) * dy) / length2))
    ex, ey = px - (ax + t * dx), py - (ay + t * dy)
    return math.sqrt(ex * ex + ey * ey)


@numba.njit(cache=True, nogil=True)
def _inside(poly: npt.NDArray[np.float64], x: float, y: float) -> bool:
    n = poly.shape[0]
    inside = False
    for i in range(n):
        x0, y0 = poly[i, 0], poly[i, 1]
        x1, y1 = poly[(i + 1) % n, 0], poly[(i + 1) % n, 1]
        if (y0 > y) != (y1 > y):
            if x < x0 + (y - y0) * (x1 - x0) / (y1 - y0):
                inside = not inside
    return inside


@numba.njit(cache=True, nogil=True)
def _edge_distance(poly: npt.NDArray[np.float64], x: float, y: float) -> float:
    n = poly.shape[0]
    best = math.inf
    for i in range(n):
        j = (i + 1) % n
        d = _segment_distance(x, y, poly[i, 0], poly[i, 1], poly[j, 0], poly[j, 1])
        best = min(best, d)
    return best


@numba.njit(cache=True, nogil=True)
def _square_gap(poly: npt.NDArray[np.float64], x0: float, y0: float, size: float) -> float:
    """Gap between the polygon and the square [x0, x0+size] x [y0, y0+size]; minus the depth of
    the overlap when they overlap (see the module docstring)."""
    n = poly.shape[0]
    xs = (x0, x0 + size, x0 + size, x0, x0 + 0.5 * size)
    ys = (y0, y0, y0 + size, y0 + size, y0 + 0.5 * size)
    depth = 0.0
    overlap = False
    for k in range(5):
        if _inside(poly, xs[k], ys[k]):
            overlap = True
            depth = max(depth, _edge_distance(poly, xs[k], ys[k]))
    for i in range(n):
        vx, vy = poly[i, 0], poly[i, 1]
        if x0 <= vx <= x0 + size and y0 <= vy <= y0 + size:
            overlap = True
            inner = min(vx - x0, x0 + size - vx, vy - y0, y0 + size - vy)
            depth = max(depth, inner)
    best = math.inf
    for i in range(n):
        j = (i + 1) % n
        ax, ay, bx, by = poly[i, 0], poly[i, 1], poly[j, 0], poly[j, 1]
        for k in range(4):
            kk = (k + 1) % 4
            # Edge against edge: crossing means overlap; else the four endpoint distances.
            cx, cy, dx, dy = xs[k], ys[k], xs[kk], ys[kk]
            o1 = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
            o2 = (bx - ax) * (dy - ay) - (by - ay) * (dx - ax)
            o3 = (dx - cx) * (ay - cy) - (dy - cy) * (ax - cx)
            o4 = (dx - cx) * (by - cy) - (dy - cy) * (bx - cx)
            if ((o1 > 0.0) != (o2 > 0.0)) and ((o3 > 0.0) != (o4 > 0.0)):
                overlap = True
            best = min(best, _segment_distance(cx, cy, ax, ay, bx, by),
                       _segment_distance(ax, ay, cx, cy, dx, dy))
    if overlap:
        return -max(depth, 1e-9)
    return best


@numba.njit(cache=True, nogil=True)
def _polygon_wall_clearance(
    occupied: npt.NDArray[np.bool_],
    origin_x: float,
    origin_y: float,
    resolution: float,
    poly: npt.NDArray[np.float64],
    horizon: float,
) -> float:
    height, width = occupied.shape
    lo_x, hi_x = poly[:, 0].min() - horizon, poly[:, 0].max() + horizon
    lo_y, hi_y = poly[:, 1].min() - horizon, poly[:, 1].max() + horizon
    ix0 = int(math.floor((lo_x - origin_x) / resolution))
    ix1 = int(math.floor((hi_x - origin_x) / resolution))
    iy0 = int(math.floor((lo_y - origin_y) / resolution))
    iy1 = int(math.floor((hi_y - origin_y) / resolution))
    best = horizon
    for iy in range(iy0, iy1 + 1):
        for ix in range(ix0, ix1 + 1):
            if 0 <= ix < width and 0 <= iy < height and not occupied[iy, ix]:
                continue
            gap = _square_gap(poly, origin_x + ix * resolution, origin_y + iy * resolution,
                              resolution)
            best = min(best, gap)
    return best


def placed_polygon(
    polygon: tuple[tuple[float, float], ...], pose: Pose2D
) -> npt.NDArray[np.float64]:
    """The base-frame ``polygon`` moved to ``pose`` (world frame), as an (N, 2) array."""
    pts = np.asarray(polygon, dtype=np.float64).reshape(-1, 2)
    c, s = math.cos(pose.theta), math.sin(pose.theta)
    out = np.empty_like(pts)
    out[:, 0] = pose.x + c * pts[:, 0] - s * pts[:, 1]
    out[:, 1] = pose.y + s * pts[:, 0] + c * pts[:, 1]
    return out


def body_wall_clearance(
    occupied: npt.NDArray[np.bool_],
    info: MapInfo,
    pose: Pose2D,
    *,
    radius: float,
    polygon: tuple[tuple[float, float], ...] = (),
    horizon: float,
) -> float:
    """Gap [m] between the robot's body at ``pose`` and the nearest occupied cell, up to
    ``horizon``: the disk of ``radius``, or ``polygon`` (base frame) when one is given.

    Negative on overlap (see the module docstring for what the value means then).
    """
    if not polygon:
        return wall_clearance(occupied, info, pose.x, pose.y, radius=radius, horizon=horizon)
    return float(_polygon_wall_clearance(
        occupied, info.origin.x, info.origin.y, info.resolution,
        placed_polygon(polygon, pose), float(horizon),
    ))


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
    square = np.array([[0.1, 0.1], [-0.1, 0.1], [-0.1, -0.1], [0.1, -0.1]])
    _polygon_wall_clearance(grid, 0.0, 0.0, 1.0, square + 0.5, 0.1)
