"""Line of sight on a cost grid: which cells a segment touches, and what crossing them costs.

Coordinates here are continuous *cell* coordinates: cell ``(ix, iy)`` covers
``[ix, ix + 1) x [iy, iy + 1)`` and its centre is ``(ix + 0.5, iy + 0.5)``. A segment is walked
with a grid traversal (Amanatides and Woo, Eurographics 1987) extended to a *supercover*: every
cell the segment passes through counts, and where it passes exactly through a cell corner the two
cells beside the corner count too, although the segment only touches them at a point. That is the
same rule as A*'s ban on corner cutting: a diagonal step between cell centres passes through the
corner shared with both orthogonal neighbours, and A* needs both passable. A near-tie (within
``1e-9`` of the segment) is treated as an exact corner, which can only make the check stricter.

A segment's cost is the line integral of the step multiplier (``grid_search.step_multipliers``)
along it, in cells: each touched cell contributes its multiplier times the length inside it. On
uniform ground that is the Euclidean length; a segment touching an impassable cell (or leaving the
grid) costs ``inf``.
"""

from __future__ import annotations

import logging
import math

import numba
import numpy as np
import numpy.typing as npt

from polynav.planning.grid_search import step_multipliers

log = logging.getLogger(__name__)

_TIE = 1e-9


@numba.njit(cache=True, nogil=True)
def _multiplier(
    costs: npt.NDArray[np.uint8], table: npt.NDArray[np.float64], ix: int, iy: int
) -> float:
    height, width = costs.shape
    if ix < 0 or iy < 0 or ix >= width or iy >= height:
        return np.inf
    return float(table[costs[iy, ix]])


@numba.njit(cache=True, nogil=True)
def segment_cost(
    costs: npt.NDArray[np.uint8],
    table: npt.NDArray[np.float64],
    x0: float,
    y0: float,
    x1: float,
    y1: float,
) -> float:
    """Line integral [cells] of the step multiplier from (x0, y0) to (x1, y1), or ``inf``.

    Args:
        costs: ``[iy, ix]`` cost grid.
        table: step multiplier per cost value (``inf`` = impassable).
        x0: start x in cell coordinates (module docstring).
        y0: start y.
        x1: end x.
        y1: end y.

    Returns:
        The cost in cells (the Euclidean length where every multiplier is 1), or ``inf`` when
        any cell of the segment's supercover is impassable or outside the grid.
    """
    ix = int(math.floor(x0))
    iy = int(math.floor(y0))
    ex = int(math.floor(x1))
    ey = int(math.floor(y1))
    m = _multiplier(costs, table, ix, iy)
    if m == np.inf or _multiplier(costs, table, ex, ey) == np.inf:
        return np.inf
    dx = x1 - x0
    dy = y1 - y0
    length = math.sqrt(dx * dx + dy * dy)
    # A segment running exactly along a grid line touches the cells on both sides of it.
    if dy == 0.0 and y0 == math.floor(y0) and dx != 0.0:
        lo = min(ix, ex)
        hi = max(ix, ex)
        for cx in range(lo, hi + 1):
            if _multiplier(costs, table, cx, iy - 1) == np.inf:
                return np.inf
    if dx == 0.0 and x0 == math.floor(x0) and dy != 0.0:
        lo = min(iy, ey)
        hi = max(iy, ey)
        for cy in range(lo, hi + 1):
            if _multiplier(costs, table, ix - 1, cy) == np.inf:
                return np.inf
    if ix == ex and iy == ey:
        return length * m
    step_x = 1 if dx > 0.0 else -1
    step_y = 1 if dy > 0.0 else -1
    if dx != 0.0:
        delta_x = 1.0 / abs(dx)
        next_x = ((ix + 1.0 - x0) if dx > 0.0 else (x0 - ix)) * delta_x
    else:
        delta_x = np.inf
        next_x = np.inf
    if dy != 0.0:
        delta_y = 1.0 / abs(dy)
        next_y = ((iy + 1.0 - y0) if dy > 0.0 else (y0 - iy)) * delta_y
    else:
        delta_y = np.inf
        next_y = np.inf
    t = 0.0
    total = 0.0
    height, width = costs.shape
    inf = np.inf
    # Each step crosses one grid line (two at a corner); this bounds the walk whatever rounding.
    # The lookups are written out: a jitted call taking the arrays would cost more than the step.
    for _ in range(abs(ex - ix) + abs(ey - iy) + 2):
        if ix == ex and iy == ey:
            break
        t_next = min(next_x, next_y)
        if t_next > 1.0:
            break
        total += (t_next - t) * m
        t = t_next
        if abs(next_x - next_y) <= _TIE:
            sx = ix + step_x
            sy = iy + step_y
            if sx < 0 or sx >= width or sy < 0 or sy >= height:
                return inf
            if table[costs[iy, sx]] == inf or table[costs[sy, ix]] == inf:
                return inf
            ix = sx
            iy = sy
            next_x += delta_x
            next_y += delta_y
        elif next_x < next_y:
            ix += step_x
            next_x += delta_x
        else:
            iy += step_y
            next_y += delta_y
        if ix < 0 or ix >= width or iy < 0 or iy >= height:
            return inf
        m = table[costs[iy, ix]]
        if m == inf:
            return inf
    total += (1.0 - t) * m
    return total * length


@numba.njit(cache=True, nogil=True)
def centre_cost(
    costs: npt.NDArray[np.uint8],
    table: npt.NDArray[np.float64],
    ax: int,
    ay: int,
    bx: int,
    by: int,
) -> float:
    """:func:`segment_cost` between the centres of cells (ax, ay) and (bx, by)."""
    return segment_cost(costs, table, ax + 0.5, ay + 0.5, bx + 0.5, by + 0.5)


def warm_up() -> None:
    """Compile the kernels on a tiny grid."""
    grid = np.zeros((3, 3), dtype=np.uint8)
    table = step_multipliers(cost_weight=1.0)
    centre_cost(grid, table, 0, 0, 2, 1)
    frozen = grid.copy()
    frozen.flags.writeable = False
    centre_cost(frozen, table, 0, 0, 2, 2)
