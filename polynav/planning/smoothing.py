"""Path post-processing: shortcut a grid path by line of sight, then space its points evenly.

A grid search returns a staircase of 8-connected moves (or, for Theta*, few vertices already).
:func:`shortcut` keeps a subset of the vertices, greedily joining each kept vertex to the farthest
later one it can reach by a straight segment that

* touches only cells the *check* table allows (the planner passes its search table, so lethal and
  inscribed cells are never entered; the supercover rule of ``line_of_sight`` includes cells the
  segment only grazes at a corner), and
* costs, as a line integral of the step multipliers, at most ``max_cost_ratio`` times the part of
  the original path it replaces. With the default ratio of 1 a shortcut never makes the path
  dearer, so it never trades the clearance the cost weights bought for a few centimetres.

Segments of the original path that cross cells the check table forbids (a start escaping from
inscribed cells) can never be shortcut, so they stay as they were. :func:`densify` then inserts
points along each segment, evenly within it and at most ``spacing`` apart, keeping every vertex:
resampling across a vertex would cut its corner, and the cut could touch a forbidden cell.
"""

from __future__ import annotations

import logging
import math

import numba
import numpy as np
import numpy.typing as npt

from polynav.planning.grid_search import step_multipliers
from polynav.planning.line_of_sight import centre_cost

log = logging.getLogger(__name__)

# A shortcut's cost may exceed the allowance by rounding noise in the two line integrals.
_COST_SLACK = 1e-9


@numba.njit(cache=True, nogil=True)
def _corners(cells: npt.NDArray[np.int64]) -> npt.NDArray[np.int64]:
    """Indices of the path's end points and of every vertex where its direction changes."""
    count = cells.shape[0]
    keep = np.empty(count, dtype=np.int64)
    keep[0] = 0
    m = 1
    for k in range(1, count - 1):
        ax = cells[k, 0] - cells[k - 1, 0]
        ay = cells[k, 1] - cells[k - 1, 1]
        bx = cells[k + 1, 0] - cells[k, 0]
        by = cells[k + 1, 1] - cells[k, 1]
        if ax * by - ay * bx != 0 or ax * bx + ay * by <= 0:
            keep[m] = k
            m += 1
    if count > 1:
        keep[m] = count - 1
        m += 1
    return keep[:m]


@numba.njit(cache=True, nogil=True)
def _shortcut(
    costs: npt.NDArray[np.uint8],
    check: npt.NDArray[np.float64],
    measure: npt.NDArray[np.float64],
    cells: npt.NDArray[np.int64],
    ratio: float,
) -> npt.NDArray[np.int64]:
    corners = _corners(cells)
    count = corners.shape[0]
    cumulative = np.zeros(count, dtype=np.float64)
    for k in range(1, count):
        a = corners[k - 1]
        b = corners[k]
        cumulative[k] = cumulative[k - 1] + centre_cost(
            costs, measure, cells[a, 0], cells[a, 1], cells[b, 0], cells[b, 1]
        )
    kept = np.empty(count, dtype=np.int64)
    kept[0] = corners[0]
    m = 1
    i = 0
    while i < count - 1:
        best = i + 1
        a = corners[i]
        for j in range(i + 2, count):
            b = corners[j]
            cost = centre_cost(costs, check, cells[a, 0], cells[a, 1], cells[b, 0], cells[b, 1])
            if cost == np.inf:
                break
            if cost <= ratio * (cumulative[j] - cumulative[i]) + _COST_SLACK:
                best = j
        kept[m] = corners[best]
        m += 1
        i = best
    return kept[:m]


def shortcut(
    costs: npt.NDArray[np.uint8],
    cells: npt.NDArray[np.int64],
    *,
    check_multipliers: npt.NDArray[np.float64],
    measure_multipliers: npt.NDArray[np.float64] | None = None,
    max_cost_ratio: float = 1.0,
) -> npt.NDArray[np.int64]:
    """Drop the vertices of a cell path that straight segments make unnecessary.

    Args:
        costs: ``[iy, ix]`` cost grid the path was planned on.
        cells: (N, 2) ``[ix, iy]`` path vertices, start first.
        check_multipliers: step multipliers a shortcut must stay finite under (the search table:
            lethal and inscribed cells are ``inf``).
        measure_multipliers: the table to price the original path with, if it may cross cells
            the check table forbids (an escape from an inscribed start); defaults to the check
            table.
        max_cost_ratio: how much dearer than the part it replaces a shortcut may be (>= 1).

    Returns:
        The kept vertices, a subsequence of ``cells`` with the same first and last cell.

    Raises:
        ValueError: a ratio below 1 or an empty path.
    """
    if not max_cost_ratio >= 1.0:
        raise ValueError(f"max_cost_ratio must be >= 1, got {max_cost_ratio}")
    path = np.ascontiguousarray(cells, dtype=np.int64).reshape(-1, 2)
    if path.shape[0] == 0:
        raise ValueError("empty path")
    if path.shape[0] <= 2:
        return path.copy()
    measure = check_multipliers if measure_multipliers is None else measure_multipliers
    kept = _shortcut(np.ascontiguousarray(costs), check_multipliers, measure, path,
                     float(max_cost_ratio))
    return path[kept]


def densify(points: npt.NDArray[np.float64], spacing: float) -> npt.NDArray[np.float64]:
    """Insert points along each segment so that neighbours are at most ``spacing`` apart.

    Every input point is kept; each segment is split into equal parts, the fewest that respect
    the spacing. Zero-length segments are kept as they are.

    Args:
        points: (N, 2) polyline [m].
        spacing: largest distance [m] between consecutive output points; 0 returns a copy.

    Returns:
        The (M, 2) densified polyline, M >= N.

    Raises:
        ValueError: a negative or non-finite spacing.
    """
    if not (spacing >= 0.0 and math.isfinite(spacing)):
        raise ValueError(f"spacing must be a finite value >= 0, got {spacing}")
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    if spacing == 0.0 or pts.shape[0] < 2:
        return pts.copy()
    deltas = np.diff(pts, axis=0)
    lengths = np.hypot(deltas[:, 0], deltas[:, 1])
    parts = np.maximum(1, np.ceil(lengths / spacing - 1e-9)).astype(np.int64)
    segment = np.repeat(np.arange(parts.shape[0]), parts)
    first = np.cumsum(parts) - parts
    fraction = (np.arange(segment.shape[0]) - first[segment]) / parts[segment]
    out = pts[segment] + deltas[segment] * fraction[:, None]
    return np.vstack([out, pts[-1:]])


def warm_up() -> None:
    """Compile the kernels on a tiny grid."""
    grid = np.zeros((3, 3), dtype=np.uint8)
    table = step_multipliers(cost_weight=1.0)
    cells = np.array([[0, 0], [1, 0], [2, 1], [2, 2]], dtype=np.int64)
    shortcut(grid, cells, check_multipliers=table)
    frozen = grid.copy()
    frozen.flags.writeable = False
    shortcut(frozen, cells, check_multipliers=table)
