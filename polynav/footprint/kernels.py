"""Numba kernels of the footprint checks: exact overlap and gap between a shape and grid cells.

A LETHAL cell is the full square it covers; the kernels look at cell geometry only for the cells
inside the footprint's bounding box at each pose, so a check costs little more than reading it.
Poses are in the grid's own frame (origin at the corner of cell (0, 0)).
"""

from __future__ import annotations

import math

import numba
import numpy as np
import numpy.typing as npt

from polynav.maps import costs

_LETHAL = costs.LETHAL
_UNKNOWN = costs.UNKNOWN
NO_CELLS = np.zeros((0, 2), dtype=np.int64)

@numba.njit(cache=True, nogil=True)
def seg_dist(px: float, py: float, ax: float, ay: float, bx: float, by: float) -> float:
    dx, dy = bx - ax, by - ay
    den = dx * dx + dy * dy
    t = 0.0
    if den > 0.0:
        t = ((px - ax) * dx + (py - ay) * dy) / den
        t = min(max(t, 0.0), 1.0)
    ex, ey = ax + t * dx - px, ay + t * dy - py
    return math.sqrt(ex * ex + ey * ey)


@numba.njit(cache=True, nogil=True)
def inside_or_on(pts: npt.NDArray[np.float64], x: float, y: float) -> bool:
    """Even-odd point-in-polygon test; points on the outline count as inside."""
    m = pts.shape[0]
    inside = False
    for i in range(m):
        ax, ay = pts[i, 0], pts[i, 1]
        bx, by = pts[(i + 1) % m, 0], pts[(i + 1) % m, 1]
        if seg_dist(x, y, ax, ay, bx, by) <= 1e-12:
            return True
        if (ay > y) != (by > y):
            xc = ax + (y - ay) * (bx - ax) / (by - ay)
            if x < xc:
                inside = not inside
    return inside


@numba.njit(cache=True, nogil=True)
def _segment_hits_box(
    ax: float, ay: float, bx: float, by: float, x0: float, y0: float, x1: float, y1: float
) -> bool:
    """Does segment a-b touch the axis-aligned box [x0, x1] x [y0, y1]? (Liang-Barsky clip)."""
    t0, t1 = 0.0, 1.0
    dx, dy = bx - ax, by - ay
    for k in range(4):
        if k == 0:
            p, q = -dx, ax - x0
        elif k == 1:
            p, q = dx, x1 - ax
        elif k == 2:
            p, q = -dy, ay - y0
        else:
            p, q = dy, y1 - ay
        if p == 0.0:
            if q < 0.0:
                return False
        else:
            r = q / p
            if p < 0.0:
                if r > t1:
                    return False
                if r > t0:
                    t0 = r
            else:
                if r < t0:
                    return False
                if r < t1:
                    t1 = r
    return True


@numba.njit(cache=True, nogil=True)
def _box_distance(px: float, py: float, x0: float, y0: float, x1: float, y1: float) -> float:
    dx = max(x0 - px, 0.0, px - x1)
    dy = max(y0 - py, 0.0, py - y1)
    return math.sqrt(dx * dx + dy * dy)


@numba.njit(cache=True, nogil=True)
def _cell_gap(
    world: npt.NDArray[np.float64],
    radius: float,
    cx: float,
    cy: float,
    x0: float,
    y0: float,
    x1: float,
    y1: float,
) -> float:
    """Gap [m] between the placed shape and the box [x0, x1] x [y0, y1]; 0 on overlap.

    ``world`` holds the placed polygon (M, 2), or is empty for a circle of ``radius`` at (cx, cy).
    """
    m = world.shape[0]
    if m == 0:
        return max(_box_distance(cx, cy, x0, y0, x1, y1) - radius, 0.0)
    mx, my = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
    if inside_or_on(world, mx, my):
        return 0.0
    best = math.inf
    for i in range(m):
        ax, ay = world[i, 0], world[i, 1]
        bx, by = world[(i + 1) % m, 0], world[(i + 1) % m, 1]
        if _segment_hits_box(ax, ay, bx, by, x0, y0, x1, y1):
            return 0.0
        # Disjoint simple shapes are nearest at a vertex of one against an edge of the other.
        best = min(best, _box_distance(ax, ay, x0, y0, x1, y1))
        best = min(best, seg_dist(x0, y0, ax, ay, bx, by))
        best = min(best, seg_dist(x1, y0, ax, ay, bx, by))
        best = min(best, seg_dist(x0, y1, ax, ay, bx, by))
        best = min(best, seg_dist(x1, y1, ax, ay, bx, by))
    return best


@numba.njit(cache=True, nogil=True)
def _place(
    verts: npt.NDArray[np.float64], x: float, y: float, theta: float, out: npt.NDArray[np.float64]
) -> None:
    c, s = math.cos(theta), math.sin(theta)
    for i in range(verts.shape[0]):
        out[i, 0] = x + c * verts[i, 0] - s * verts[i, 1]
        out[i, 1] = y + s * verts[i, 0] + c * verts[i, 1]


@numba.njit(cache=True, nogil=True)
def _is_obstacle(grid: npt.NDArray[np.uint8], ix: int, iy: int, unknown_is_lethal: bool) -> bool:
    h, w = grid.shape
    if ix < 0 or iy < 0 or ix >= w or iy >= h:
        return unknown_is_lethal
    v = grid[iy, ix]
    if v == _LETHAL:
        return True
    return unknown_is_lethal and v == _UNKNOWN


@numba.njit(cache=True, nogil=True)
def _min_gap(
    grid: npt.NDArray[np.uint8],
    res: float,
    verts: npt.NDArray[np.float64],
    radius: float,
    x: float,
    y: float,
    theta: float,
    reach: float,
    horizon: float,
    unknown_is_lethal: bool,
    world: npt.NDArray[np.float64],
) -> float:
    """Smallest gap up to ``horizon`` from the placed shape to an obstacle cell within ``reach``."""
    _place(verts, x, y, theta, world)
    span = reach + horizon
    ix0 = int(math.floor((x - span) / res))
    ix1 = int(math.floor((x + span) / res))
    iy0 = int(math.floor((y - span) / res))
    iy1 = int(math.floor((y + span) / res))
    best = horizon
    for iy in range(iy0, iy1 + 1):
        y0 = iy * res
        for ix in range(ix0, ix1 + 1):
            if not _is_obstacle(grid, ix, iy, unknown_is_lethal):
                continue
            x0 = ix * res
            # The nearest the cell can be to any part of the shape is its distance to the
            # circumscribed circle; skip the exact test when even that is no better.
            if _box_distance(x, y, x0, y0, x0 + res, y0 + res) - reach >= best:
                continue
            gap = _cell_gap(world, radius, x, y, x0, y0, x0 + res, y0 + res)
            if gap < best:
                best = gap
                if best <= 0.0:
                    return 0.0
    return best


@numba.njit(cache=True, nogil=True)
def _overlaps(
    grid: npt.NDArray[np.uint8],
    res: float,
    verts: npt.NDArray[np.float64],
    radius: float,
    x: float,
    y: float,
    theta: float,
    reach: float,
    unknown_is_lethal: bool,
    world: npt.NDArray[np.float64],
    ignore: npt.NDArray[np.int64],
) -> bool:
    """Does the shape placed at (x, y, theta) overlap an obstacle cell not in ``ignore``?"""
    _place(verts, x, y, theta, world)
    ix0 = int(math.floor((x - reach) / res))
    ix1 = int(math.floor((x + reach) / res))
    iy0 = int(math.floor((y - reach) / res))
    iy1 = int(math.floor((y + reach) / res))
    for iy in range(iy0, iy1 + 1):
        y0 = iy * res
        for ix in range(ix0, ix1 + 1):
            if not _is_obstacle(grid, ix, iy, unknown_is_lethal):
                continue
            x0 = ix * res
            if _box_distance(x, y, x0, y0, x0 + res, y0 + res) > reach:
                continue
            if _cell_gap(world, radius, x, y, x0, y0, x0 + res, y0 + res) <= 0.0:
                ignored = False
                for k in range(ignore.shape[0]):
                    if ignore[k, 0] == ix and ignore[k, 1] == iy:
                        ignored = True
                        break
                if not ignored:
                    return True
    return False


@numba.njit(cache=True, nogil=True)
def overlapped_cells(
    grid: npt.NDArray[np.uint8],
    res: float,
    verts: npt.NDArray[np.float64],
    radius: float,
    pose: npt.NDArray[np.float64],
    unknown_is_lethal: bool,
) -> npt.NDArray[np.int64]:
    """The obstacle cells (K, 2) of (ix, iy) the shape at ``pose`` overlaps."""
    world = np.empty_like(verts)
    x, y = pose[0], pose[1]
    _place(verts, x, y, pose[2], world)
    reach = _reach(verts, radius)
    ix0 = int(math.floor((x - reach) / res))
    ix1 = int(math.floor((x + reach) / res))
    iy0 = int(math.floor((y - reach) / res))
    iy1 = int(math.floor((y + reach) / res))
    out = np.empty(((ix1 - ix0 + 1) * (iy1 - iy0 + 1), 2), dtype=np.int64)
    n = 0
    for iy in range(iy0, iy1 + 1):
        y0 = iy * res
        for ix in range(ix0, ix1 + 1):
            if not _is_obstacle(grid, ix, iy, unknown_is_lethal):
                continue
            x0 = ix * res
            if _cell_gap(world, radius, x, y, x0, y0, x0 + res, y0 + res) <= 0.0:
                out[n, 0] = ix
                out[n, 1] = iy
                n += 1
    return out[:n].copy()


@numba.njit(cache=True, nogil=True)
def _reach(verts: npt.NDArray[np.float64], radius: float) -> float:
    reach = radius
    for i in range(verts.shape[0]):
        reach = max(reach, math.sqrt(verts[i, 0] ** 2 + verts[i, 1] ** 2))
    return reach


@numba.njit(cache=True, nogil=True)
def first_hit(
    grid: npt.NDArray[np.uint8],
    res: float,
    verts: npt.NDArray[np.float64],
    radius: float,
    poses: npt.NDArray[np.float64],
    unknown_is_lethal: bool,
    ignore: npt.NDArray[np.int64],
) -> int:
    world = np.empty_like(verts)
    reach = _reach(verts, radius)
    for k in range(poses.shape[0]):
        if _overlaps(grid, res, verts, radius, poses[k, 0], poses[k, 1], poses[k, 2],
                     reach, unknown_is_lethal, world, ignore):
            return k
    return -1


@numba.njit(cache=True, nogil=True)
def mask(
    grid: npt.NDArray[np.uint8],
    res: float,
    verts: npt.NDArray[np.float64],
    radius: float,
    poses: npt.NDArray[np.float64],
    unknown_is_lethal: bool,
) -> npt.NDArray[np.bool_]:
    world = np.empty_like(verts)
    reach = _reach(verts, radius)
    out = np.zeros(poses.shape[0], dtype=np.bool_)
    for k in range(poses.shape[0]):
        out[k] = _overlaps(grid, res, verts, radius, poses[k, 0], poses[k, 1], poses[k, 2],
                           reach, unknown_is_lethal, world, NO_CELLS)
    return out


@numba.njit(cache=True, nogil=True)
def clearance_gaps(
    grid: npt.NDArray[np.uint8],
    res: float,
    verts: npt.NDArray[np.float64],
    radius: float,
    poses: npt.NDArray[np.float64],
    horizon: float,
    unknown_is_lethal: bool,
) -> npt.NDArray[np.float64]:
    world = np.empty_like(verts)
    reach = _reach(verts, radius)
    out = np.empty(poses.shape[0], dtype=np.float64)
    for k in range(poses.shape[0]):
        out[k] = _min_gap(grid, res, verts, radius, poses[k, 0], poses[k, 1], poses[k, 2],
                          reach, horizon, unknown_is_lethal, world)
    return out


overlaps_at = _overlaps
"""Public name of the single-placement overlap test, for searches that place the body cell by
cell (:mod:`polynav.planning.lattice`)."""

reach_of = _reach
"""Public name of the body's reach [m] (its circumscribed radius)."""
