"""Theta*: any-angle paths on a cost grid (Daniel, Nash, Koenig and Felner, JAIR 39, 2010).

Theta* is A* whose nodes may take as parent any cell they can see, not only a neighbour: when a
cell ``s`` is expanded, each neighbour ``n`` gets the cheaper of

* path 1, the grid step ``s -> n`` (with ``s`` as parent), and
* path 2, the straight segment ``parent(s) -> n`` when that segment is clear,

so paths bend only where an obstacle (or a change of cost) makes them. Neighbours follow A*'s
rules exactly: 8-connected and no corner cutting. Segments are checked and priced by
``line_of_sight.segment_cost``: the line integral of the step multiplier over the segment's
supercover, ``inf`` when it touches an impassable cell. A grid step costs the same under that
rule (half of each cell's multiplier times the step), so the two paths compare like for like.
The heuristic is the Euclidean distance, admissible since every multiplier is at least 1.

This is the lazy variant (Nash, Koenig and Tovey, AAAI 2010): a generated cell first assumes its
grandparent's segment at the Euclidean length, a lower bound of its price, and the segment is
walked only when the cell is popped. If it is blocked or dearer, the cell falls back to its best
closed grid neighbour, and goes back into the queue if its true cost exceeds its key. One segment
walk per expansion instead of one per generated neighbour made it about twice as fast on Nav2's
2000 x 2000 benchmark maps, with the same path costs.

Theta* is not guaranteed optimal among any-angle paths, but its paths are never longer than the
8-connected A* path on uniform ground in practice, and are much straighter. The start cell must
be passable under the table (``grid_planner`` leaves an inscribed or unknown start with A* first).
"""

from __future__ import annotations

import logging
import math
from typing import cast

import numba
import numpy as np
import numpy.typing as npt

from polynav.planning import heap
from polynav.planning.grid_search import (
    CellPath,
    SearchBuffers,
    check_key_range,
    step_multipliers,
)
from polynav.planning.line_of_sight import centre_cost

log = logging.getLogger(__name__)

SQRT2 = math.sqrt(2.0)
_TIE = 1e-9

_DX = np.array([1, -1, 0, 0, 1, -1, 1, -1], dtype=np.int64)
_DY = np.array([0, 0, 1, -1, 1, 1, -1, -1], dtype=np.int64)


@numba.njit(cache=True, nogil=True)
def _euclid(x: int, y: int, gx: int, gy: int) -> float:
    dx = x - gx
    dy = y - gy
    return math.sqrt(dx * dx + dy * dy)


@numba.njit(cache=True, nogil=True)
def _compact(queue: npt.NDArray[np.int64], n: int, g: npt.NDArray[np.float64],
             state: npt.NDArray[np.int32], stamp: int, gx: int, gy: int, width: int) -> int:
    """Drop entries of closed cells and superseded ``g`` values, then restore the heap."""
    m = 0
    for k in range(n):
        key = queue[2 * k]
        tie = queue[2 * k + 1]
        cell = tie & heap.CELL_MASK
        y = cell // width
        x = cell - y * width
        s = state[cell]
        if (s == stamp or s == stamp + 2) and key == heap.f_key(g[cell] + _euclid(x, y, gx, gy)):
            queue[2 * m] = key
            queue[2 * m + 1] = tie
            m += 1
    heap.heapify(queue, m)
    return m


@numba.njit(cache=True, nogil=True)
def _passable_sides(
    costs: npt.NDArray[np.uint8], table: npt.NDArray[np.float64], x: int, y: int
) -> tuple[bool, bool, bool, bool]:
    height, width = costs.shape
    east = x + 1 < width and table[costs[y, x + 1]] != np.inf
    west = x > 0 and table[costs[y, x - 1]] != np.inf
    north = y + 1 < height and table[costs[y + 1, x]] != np.inf
    south = y > 0 and table[costs[y - 1, x]] != np.inf
    return east, west, north, south


@numba.njit(cache=True, nogil=True)
def _verify(
    costs: npt.NDArray[np.uint8],
    table: npt.NDArray[np.float64],
    u: int,
    g: npt.NDArray[np.float64],
    state: npt.NDArray[np.int32],
    parent: npt.NDArray[np.int64],
    closed: int,
) -> float:
    """Lazy Theta*'s SetVertex: price ``u``'s assumed segment from its parent for real, and fall
    back to the best closed grid neighbour if the segment is blocked or dearer. Returns the
    true cost, also written to ``g[u]``."""
    height, width = costs.shape
    y = u // width
    x = u - y * width
    p = parent[u]
    py = p // width
    px = p - py * width
    best = g[p] + centre_cost(costs, table, px, py, x, y)
    best_parent = p
    mu = table[costs[y, x]]
    east, west, north, south = _passable_sides(costs, table, x, y)
    for d in range(8):
        dx = _DX[d]
        dy = _DY[d]
        horizontal = east if dx > 0 else west
        vertical = north if dy > 0 else south
        if d < 4:
            if not (horizontal if dx != 0 else vertical):
                continue
        elif not (horizontal and vertical):
            continue
        n = (y + dy) * width + x + dx
        if state[n] != closed:
            continue
        step = 1.0 if d < 4 else SQRT2
        through = g[n] + 0.5 * step * (table[costs[y + dy, x + dx]] + mu)
        # Ties keep the straight segment (fewer vertices, same cost).
        if through < best - _TIE:
            best = through
            best_parent = n
    g[u] = best
    parent[u] = best_parent
    return float(best)


@numba.njit(cache=True, nogil=True)
def search(
    costs: npt.NDArray[np.uint8],
    table: npt.NDArray[np.float64],
    sx: int,
    sy: int,
    gx: int,
    gy: int,
    g: npt.NDArray[np.float64],
    state: npt.NDArray[np.int32],
    parent: npt.NDArray[np.int64],
    queue: npt.NDArray[np.int64],
    stamp: int,
) -> tuple[int, float, int]:
    """The Lazy Theta* kernel over plain arrays (module docstring).

    Args:
        costs: C-contiguous ``[iy, ix]`` cost grid.
        table: step multiplier per cost value (``inf`` = impassable).
        sx: start column (its cell must be passable).
        sy: start row.
        gx: goal column.
        gy: goal row.
        g: cost so far per flat cell, valid where ``state`` holds this stamp.
        state: ``stamp`` open with an assumed segment, ``stamp + 2`` open and priced,
            ``stamp + 1`` closed, anything else unseen (stamps advance by 4 per query).
        parent: flat index of each cell's parent (the start is its own parent).
        queue: binary heap of ``(key, tie)`` words (``heap``); stale entries are compacted away
            when it fills.
        stamp: this query's generation stamp (a multiple of 4, > 0).

    Returns:
        ``(status, cost [cells], expansions)``: status 1 found, 0 no path, -1 the heap is full of
        live entries (grow it and search again).
    """
    height, width = costs.shape
    closed = stamp + 1
    priced = stamp + 2
    capacity = queue.shape[0] // 2
    start = sy * width + sx
    goal = gy * width + gx
    g[start] = 0.0
    state[start] = priced
    parent[start] = start
    h0 = _euclid(sx, sy, gx, gy)
    n = heap.push(queue, 0, heap.f_key(h0), heap.tie_key(h0, start))
    expansions = 0
    while n > 0:
        u = queue[1] & heap.CELL_MASK
        key = queue[0]
        n = heap.pop(queue, n)
        s = state[u]
        if s == closed:
            continue
        y = u // width
        x = u - y * width
        if s == stamp:
            state[u] = priced
            assumed = g[u]
            true = _verify(costs, table, u, g, state, parent, closed)
            if true > assumed + _TIE:
                # Dearer than its key said: back in the queue at its true place.
                hu = _euclid(x, y, gx, gy)
                if n == capacity:
                    n = _compact(queue, n, g, state, stamp, gx, gy, width)
                n = heap.push(queue, n, heap.f_key(true + hu), heap.tie_key(hu, u))
                continue
        elif key != heap.f_key(g[u] + _euclid(x, y, gx, gy)):
            continue  # a superseded entry of a cell queued again since
        state[u] = closed
        expansions += 1
        if u == goal:
            return 1, g[u], expansions
        p = parent[u]
        py = p // width
        px = p - py * width
        mu = table[costs[y, x]]
        east, west, north, south = _passable_sides(costs, table, x, y)
        for d in range(8):
            dx = _DX[d]
            dy = _DY[d]
            horizontal = east if dx > 0 else west
            vertical = north if dy > 0 else south
            if d < 4:
                if not (horizontal if dx != 0 else vertical):
                    continue
            elif not (horizontal and vertical):
                continue
            vx = x + dx
            vy = y + dy
            v = vy * width + vx
            sv = state[v]
            if sv == closed:
                continue
            mv = table[costs[vy, vx]]
            if mv == np.inf:
                continue
            step = 1.0 if d < 4 else SQRT2
            best = g[u] + 0.5 * step * (mu + mv)
            best_parent = u
            best_state = priced
            if p != u:
                # Assume the parent sees v: the Euclidean length is a lower bound of the
                # segment's price (every multiplier is at least 1), checked when v is popped.
                # Ties go to the straight segment, so collinear vertices do not pile up.
                through = g[p] + _euclid(px, py, vx, vy)
                if through <= best + _TIE:
                    best = through
                    best_parent = p
                    best_state = stamp
            if (sv == stamp or sv == priced) and g[v] <= best:
                continue
            g[v] = best
            state[v] = best_state
            parent[v] = best_parent
            if n == capacity:
                n = _compact(queue, n, g, state, stamp, gx, gy, width)
                if n == capacity:
                    return -1, np.inf, expansions
            hv = _euclid(vx, vy, gx, gy)
            n = heap.push(queue, n, heap.f_key(best + hv), heap.tie_key(hv, v))
    return 0, np.inf, expansions


@numba.njit(cache=True, nogil=True)
def trace(
    parent: npt.NDArray[np.int64], width: int, start: int, goal: int
) -> npt.NDArray[np.int64]:
    """The (N, 2) ``[ix, iy]`` path vertices from start to goal along the parent links."""
    count = 1
    c = goal
    while c != start:
        c = parent[c]
        count += 1
    cells = np.empty((count, 2), dtype=np.int64)
    c = goal
    for k in range(count - 1, -1, -1):
        cells[k, 0] = c % width
        cells[k, 1] = c // width
        c = parent[c]
    return cells


class ThetaStar:
    """Theta* with buffers kept for the last grid size (not thread-safe: one per planner)."""

    def __init__(self) -> None:
        self._buffers = SearchBuffers()

    def search(
        self,
        costs: npt.NDArray[np.uint8],
        start: tuple[int, int],
        goal: tuple[int, int],
        *,
        multipliers: npt.NDArray[np.float64],
        escape_multipliers: npt.NDArray[np.float64] | None = None,
    ) -> CellPath | None:
        """An any-angle path from ``start`` to ``goal`` (cells ``(ix, iy)``), or None.

        Args:
            costs: ``[iy, ix]`` uint8 cost grid.
            start: start cell, inside the grid and passable under ``multipliers``.
            goal: goal cell, inside the grid.
            multipliers: step multipliers per cost (``grid_search.step_multipliers``).
            escape_multipliers: not supported; Theta* cannot leave an impassable start.

        Returns:
            The path's vertices with its cost [cells], or None when the goal is unreachable.

        Raises:
            ValueError: start or goal outside the grid, an impassable start, or an escape table.
        """
        if escape_multipliers is not None:
            raise ValueError("Theta* does not escape an impassable start; use A* for that leg")
        grid = np.ascontiguousarray(costs)
        height, width = grid.shape
        sx, sy = int(start[0]), int(start[1])
        gx, gy = int(goal[0]), int(goal[1])
        if not (0 <= sx < width and 0 <= sy < height and 0 <= gx < width and 0 <= gy < height):
            raise ValueError(f"start {start} or goal {goal} outside the {width}x{height} grid")
        if not np.isfinite(multipliers[grid[sy, sx]]):
            raise ValueError(f"start {start} is impassable")
        check_key_range(multipliers, (height, width))
        buffers = self._buffers
        while True:
            stamp = buffers.next_stamp((height, width), parent_dtype=np.int64, stride=4)
            parents = cast("npt.NDArray[np.int64]", buffers.parent)  # int64 by next_stamp
            status, cost, expansions = search(
                grid, multipliers, sx, sy, gx, gy, buffers.g, buffers.state, parents,
                buffers.heap, stamp,
            )
            if status >= 0:
                break
            buffers.grow_queue()
        if status == 0:
            log.debug("Theta*: no path %s -> %s after %d expansions", start, goal, expansions)
            return None
        cells = trace(parents, width, sy * width + sx, gy * width + gx)
        return CellPath(cells=cells, cost=float(cost), expansions=int(expansions))

    def closed(self, cells: npt.NDArray[np.int64]) -> npt.NDArray[np.bool_]:
        """Which ``[ix, iy]`` cells the last search closed; after a failed search, exactly the
        cells reachable from its start."""
        return self._buffers.closed(cells)


def warm_up() -> None:
    """Compile the kernels on a tiny grid, for writable and read-only cost arrays."""
    heap.warm_up()
    grid = np.zeros((4, 4), dtype=np.uint8)
    grid[1, 1] = 254
    table = step_multipliers(cost_weight=1.0)
    planner = ThetaStar()
    planner.search(grid, (0, 0), (3, 3), multipliers=table)
    frozen = grid.copy()
    frozen.flags.writeable = False
    planner.search(frozen, (0, 0), (3, 2), multipliers=table)
