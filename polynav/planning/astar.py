"""Grid A*: 8-connected, octile heuristic, no corner cutting, cost-aware; a numba kernel.

The search (Hart, Nilsson and Raphael, IEEE TSSC 1968) runs on a ``costs[iy, ix]`` grid through a
step-multiplier table (``grid_search.step_multipliers``): an orthogonal step costs 1 and a diagonal
one sqrt 2 [cells], times the multiplier of the cell entered. A diagonal move needs *both*
orthogonally adjacent cells passable, so a path never squeezes between two blocked cells that
touch at a corner; with all multipliers 1 this is exactly the metric of the MovingAI benchmark
lengths. The octile distance is a consistent heuristic because every multiplier is at least 1, so
the first time a cell is closed its cost is final and the goal is popped with the optimal cost.

What keeps it fast on large maps (DESIGN §8 asks for pyastar2d's speed or better):

* buffers are reused across queries through a generation stamp (``grid_search.SearchBuffers``),
  so a query never clears ``O(H * W)`` memory;
* equal-``f`` ties go to the larger ``g`` on quantised keys (``heap``), which on open floors
  expands little more than the cells of the path itself;
* the open list is a bucket queue over a small heap, and the best child of an expansion skips the
  queue when nothing queued comes first (:func:`search`);
* the hot loop makes no jitted call that takes an array (``heap`` explains why).

**Escaping an inscribed start.** A robot pressed against a wall sits in an INSCRIBED cell, from
which every neighbour may be inscribed too. With an escape table, cells that only it allows
(``lethal_threshold <= cost < escape_below``) may be entered only from another such cell: the
path leaves the start region through those cells and, once out, never re-enters them. This is a
plain directed graph, so the search stays optimal over every way out.

:class:`AStar` is the object callers keep: it owns the buffers for the last grid size it saw.
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

log = logging.getLogger(__name__)

SQRT2 = math.sqrt(2.0)

BUCKET_SHIFT = 30
"""A bucket spans ``2**30`` key quanta, a quarter cell of ``f`` (measured as the best width)."""

# Neighbour directions: E, W, N, S, NE, NW, SE, SW as (dx, dy); the parent array stores the index.
_DX = np.array([1, -1, 0, 0, 1, -1, 1, -1], dtype=np.int64)
_DY = np.array([0, 0, 1, -1, 1, 1, -1, -1], dtype=np.int64)


@numba.njit(cache=True, nogil=True)
def _octile(x: int, y: int, gx: int, gy: int) -> float:
    dx = abs(x - gx)
    dy = abs(y - gy)
    if dx < dy:
        return dy + (SQRT2 - 1.0) * dx
    return dx + (SQRT2 - 1.0) * dy


@numba.njit(cache=True, nogil=True)
def _live(cell: int, key: int, g: npt.NDArray[np.float64], state: npt.NDArray[np.int32],
          stamp: int, gx: int, gy: int, width: int) -> bool:
    """True if an open-list entry still stands for its cell's best ``g`` (not closed, not stale)."""
    if state[cell] != stamp:
        return False
    y = cell // width
    x = cell - y * width
    return key == heap.f_key(g[cell] + _octile(x, y, gx, gy))


@numba.njit(cache=True, nogil=True)
def _compact_heap(queue: npt.NDArray[np.int64], n: int, g: npt.NDArray[np.float64],
                  state: npt.NDArray[np.int32], stamp: int, gx: int, gy: int, width: int) -> int:
    m = 0
    for k in range(n):
        key = queue[2 * k]
        tie = queue[2 * k + 1]
        if _live(tie & heap.CELL_MASK, key, g, state, stamp, gx, gy, width):
            queue[2 * m] = key
            queue[2 * m + 1] = tie
            m += 1
    heap.heapify(queue, m)
    return m


@numba.njit(cache=True, nogil=True)
def _compact_pool(pool: npt.NDArray[np.int64], nxt: npt.NDArray[np.int64],
                  heads: npt.NDArray[np.int64], top: int,
                  g: npt.NDArray[np.float64], state: npt.NDArray[np.int32], stamp: int,
                  gx: int, gy: int, width: int) -> int:
    """Squeeze stale entries out of a full bucket pool (no free slot left) and re-chain the
    live ones; returns how many remain, all in ``pool[:2 * count]``."""
    mask = heads.shape[0] - 1
    heads[:] = -1
    m = 0
    for k in range(top):
        key = pool[2 * k]
        tie = pool[2 * k + 1]
        if not _live(tie & heap.CELL_MASK, key, g, state, stamp, gx, gy, width):
            continue
        pool[2 * m] = key
        pool[2 * m + 1] = tie
        slot = (key >> BUCKET_SHIFT) & mask
        nxt[m] = heads[slot]
        heads[slot] = m
        m += 1
    return m


@numba.njit(cache=True, nogil=True)
def search(
    costs: npt.NDArray[np.uint8],
    tables: npt.NDArray[np.float64],
    escape_lo: int,
    escape_hi: int,
    sx: int,
    sy: int,
    gx: int,
    gy: int,
    g: npt.NDArray[np.float64],
    state: npt.NDArray[np.int32],
    parent: npt.NDArray[np.int8],
    queue: npt.NDArray[np.int64],
    pool: npt.NDArray[np.int64],
    nxt: npt.NDArray[np.int64],
    heads: npt.NDArray[np.int64],
    stamp: int,
) -> tuple[int, float, int]:
    """The A* kernel over plain arrays; see the module docstring for the model.

    The open list is a bucket queue: entries whose key falls in the current bucket (a quarter
    cell of ``f``) sit in a binary heap, later ones are chained unsorted per bucket and heapified
    when their bucket comes up. Most pushes are then an append, and the heap stays small enough
    for the cache. A node's ``f`` exceeds its parent's by at most ``sqrt 2 (m + 1)`` for the
    largest multiplier ``m``, so ``heads`` is a ring of buckets a power of two long covering that.
    Among the children of an expanded node, the best one is expanded next without entering the
    queue at all when nothing queued comes before it.

    Args:
        costs: C-contiguous ``[iy, ix]`` cost grid.
        tables: 512 step multipliers: the normal table (``inf`` = impassable) then the escape
            table, used when expanding a cell whose cost lies in ``[escape_lo, escape_hi)``.
        escape_lo: first cost of the escape band (pass an empty band for none).
        escape_hi: end (exclusive) of the escape band.
        sx: start column.
        sy: start row.
        gx: goal column.
        gy: goal row.
        g: cost so far per flat cell, valid where ``state`` holds this stamp.
        state: ``stamp`` open, ``stamp + 1`` closed, anything else unseen.
        parent: index into the E, W, N, S, NE, NW, SE, SW table of the move that reached a cell.
        queue: heap of the current bucket, ``2 * capacity`` words.
        pool: entries of later buckets, ``2 * capacity`` words.
        nxt: chain links of ``pool``, ``capacity`` entries.
        heads: first pool entry per bucket slot; length a power of two (see above).
        stamp: this query's generation stamp (even, > 0).

    Returns:
        ``(status, cost [cells], expansions)`` with status 1 found, 0 no path, -1 the open list
        is full even after compaction (grow it and search again). The start is expanded
        whatever its own cost.
    """
    height, width = costs.shape
    flat = costs.reshape(height * width)
    inf = np.inf
    closed = stamp + 1
    capacity = nxt.shape[0]
    ring = heads.shape[0] - 1
    inv_width = 1.0 / width
    heads[:] = -1
    free = -1
    top = 0
    pending = 0
    none = np.int64(0x7FFFFFFFFFFFFFFF)
    start = sy * width + sx
    goal = gy * width + gx
    g[start] = 0.0
    state[start] = stamp
    key0 = heap.f_key(_octile(sx, sy, gx, gy))
    queue[0] = key0
    queue[1] = start
    n = 1
    bucket = key0 >> BUCKET_SHIFT
    expansions = 0
    u = -1
    while True:
        if u < 0:
            if n == 0:
                if pending == 0:
                    break
                while True:
                    bucket += 1
                    if heads[bucket & ring] >= 0:
                        break
                slot = bucket & ring
                k = heads[slot]
                first = k
                last = k
                heads[slot] = -1
                while k >= 0:
                    pending -= 1
                    tie = pool[2 * k + 1]
                    if state[tie & heap.CELL_MASK] != closed:
                        queue[2 * n] = pool[2 * k]
                        queue[2 * n + 1] = tie
                        n += 1
                    last = k
                    k = nxt[k]
                nxt[last] = free
                free = first
                heap.heapify(queue, n)
                continue
            u = queue[1] & heap.CELL_MASK
            # Pop, inlined (see the heap module on numba call overhead).
            n -= 1
            if n > 0:
                key = queue[2 * n]
                tie = queue[2 * n + 1]
                j = 0
                while True:
                    c = 2 * j + 1
                    if c >= n:
                        break
                    ck = queue[2 * c]
                    ct = queue[2 * c + 1]
                    if c + 1 < n:
                        rk = queue[2 * c + 2]
                        rt = queue[2 * c + 3]
                        if rk < ck or (rk == ck and rt < ct):
                            ck = rk
                            ct = rt
                            c += 1
                    if not (ck < key or (ck == key and ct < tie)):
                        break
                    queue[2 * j] = ck
                    queue[2 * j + 1] = ct
                    j = c
                queue[2 * j] = key
                queue[2 * j + 1] = tie
            if state[u] == closed:
                u = -1
                continue
        state[u] = closed
        expansions += 1
        gu = g[u]
        if u == goal:
            return 1, gu, expansions
        # Exact for any grid below 2**31 cells, and cheaper than an integer division.
        y = int((u + 0.5) * inv_width)
        x = u - y * width
        cu = flat[u]
        base = 256 if escape_lo <= cu and cu < escape_hi else 0
        me = tables[base + flat[u + 1]] if x + 1 < width else inf
        mw = tables[base + flat[u - 1]] if x > 0 else inf
        mn = tables[base + flat[u + width]] if y + 1 < height else inf
        ms = tables[base + flat[u - width]] if y > 0 else inf
        best_key = none
        best_tie = none
        following = -1
        # Directions 0..7 are the moves (a diagonal needs both orthogonal neighbours passable,
        # which also proves it inside the grid); step 8 settles the best child kept aside.
        for d in range(9):
            if d == 8:
                if best_key == none:
                    break
                if n > 0:
                    take = best_key < queue[0] or (best_key == queue[0] and best_tie <= queue[1])
                else:
                    take = (best_key >> BUCKET_SHIFT) <= bucket
                if take:
                    following = int(best_tie & heap.CELL_MASK)
                    break
                key = best_key
                tie = best_tie
            else:
                if d == 0:
                    if me == inf:
                        continue
                    v = u + 1
                    vx = x + 1
                    vy = y
                    gv = gu + me
                elif d == 1:
                    if mw == inf:
                        continue
                    v = u - 1
                    vx = x - 1
                    vy = y
                    gv = gu + mw
                elif d == 2:
                    if mn == inf:
                        continue
                    v = u + width
                    vx = x
                    vy = y + 1
                    gv = gu + mn
                elif d == 3:
                    if ms == inf:
                        continue
                    v = u - width
                    vx = x
                    vy = y - 1
                    gv = gu + ms
                else:
                    if d == 4:
                        if mn == inf or me == inf:
                            continue
                        v = u + width + 1
                        vx = x + 1
                        vy = y + 1
                    elif d == 5:
                        if mn == inf or mw == inf:
                            continue
                        v = u + width - 1
                        vx = x - 1
                        vy = y + 1
                    elif d == 6:
                        if ms == inf or me == inf:
                            continue
                        v = u - width + 1
                        vx = x + 1
                        vy = y - 1
                    else:
                        if ms == inf or mw == inf:
                            continue
                        v = u - width - 1
                        vx = x - 1
                        vy = y - 1
                    m = tables[base + flat[v]]
                    if m == inf:
                        continue
                    gv = gu + SQRT2 * m
                s = state[v]
                if s == closed or (s == stamp and g[v] <= gv):
                    continue
                g[v] = gv
                state[v] = stamp
                parent[v] = d
                hv = _octile(vx, vy, gx, gy)
                key = heap.f_key(gv + hv)
                tie = heap.tie_key(hv, v)
                if key < best_key or (key == best_key and tie < best_tie):
                    key, best_key = best_key, key
                    tie, best_tie = best_tie, tie
                    if key == none:
                        continue
            # Queue (key, tie): into the heap if its bucket is current, else onto its bucket.
            if (key >> BUCKET_SHIFT) <= bucket:
                if n == capacity:
                    n = _compact_heap(queue, n, g, state, stamp, gx, gy, width)
                    if n == capacity:
                        return -1, inf, expansions
                j = n
                while j > 0:
                    p = (j - 1) >> 1
                    pk = queue[2 * p]
                    pt = queue[2 * p + 1]
                    if not (key < pk or (key == pk and tie < pt)):
                        break
                    queue[2 * j] = pk
                    queue[2 * j + 1] = pt
                    j = p
                queue[2 * j] = key
                queue[2 * j + 1] = tie
                n += 1
            else:
                if free < 0:
                    if top == capacity:
                        top = _compact_pool(pool, nxt, heads, top, g, state, stamp, gx, gy, width)
                        pending = top
                        if top == capacity:
                            return -1, inf, expansions
                    k = top
                    top += 1
                else:
                    k = free
                    free = nxt[k]
                slot = (key >> BUCKET_SHIFT) & ring
                pool[2 * k] = key
                pool[2 * k + 1] = tie
                nxt[k] = heads[slot]
                heads[slot] = k
                pending += 1
        u = following
    return 0, inf, expansions


@numba.njit(cache=True, nogil=True)
def trace(
    parent: npt.NDArray[np.int8],
    width: int,
    sx: int,
    sy: int,
    gx: int,
    gy: int,
) -> npt.NDArray[np.int64]:
    """The (N, 2) ``[ix, iy]`` cells from start to goal, following the parent moves back."""
    x = gx
    y = gy
    count = 1
    while x != sx or y != sy:
        d = parent[y * width + x]
        x -= _DX[d]
        y -= _DY[d]
        count += 1
    cells = np.empty((count, 2), dtype=np.int64)
    x = gx
    y = gy
    for k in range(count - 1, -1, -1):
        cells[k, 0] = x
        cells[k, 1] = y
        if k > 0:
            d = parent[y * width + x]
            x -= _DX[d]
            y -= _DY[d]
    return cells


class AStar:
    """Grid A* with buffers kept for the last grid size (not thread-safe: one per planner).

    Args:
        capacity: open-list entries to preallocate; the default (one per cell) never runs out.
            A smaller one is grown on demand (tests use it to exercise compaction).
    """

    def __init__(self, *, capacity: int | None = None) -> None:
        self._buffers = SearchBuffers(capacity)
        # The tables of the last query, reused while the caller passes the same arrays (the
        # cached ``step_multipliers`` tables): on small maps this set-up would cost more than
        # the search.
        self._prepared_for: tuple[object, object, int, int] | None = None
        self._prepared: tuple[npt.NDArray[np.float64], int, int, npt.NDArray[np.int64]] = (
            np.empty(0), 0, 0, np.empty(0, dtype=np.int64)
        )

    def search(
        self,
        costs: npt.NDArray[np.uint8],
        start: tuple[int, int],
        goal: tuple[int, int],
        *,
        multipliers: npt.NDArray[np.float64],
        escape_multipliers: npt.NDArray[np.float64] | None = None,
    ) -> CellPath | None:
        """The cheapest 8-connected path from ``start`` to ``goal``, or None if there is none.

        Args:
            costs: ``[iy, ix]`` uint8 cost grid.
            start: start cell ``(ix, iy)``, inside the grid; expanded whatever its cost.
            goal: goal cell ``(ix, iy)``, inside the grid; reached only if passable.
            multipliers: step multipliers per cost (``grid_search.step_multipliers``); treated
                as immutable (the read-only cached tables are), since set-up derived from them
                is reused while the same array comes back.
            escape_multipliers: optional table that also allows a band of costs at and above
                the lethal threshold, entered only from cells of that band (module docstring).
                Used when the start itself lies in that band.

        Returns:
            The cell path with its cost [cells], or None when the goal is unreachable.

        Raises:
            ValueError: start or goal outside the grid, or a grid too large for the keys.
        """
        grid = np.ascontiguousarray(costs)
        height, width = grid.shape
        sx, sy = int(start[0]), int(start[1])
        gx, gy = int(goal[0]), int(goal[1])
        if not (0 <= sx < width and 0 <= sy < height and 0 <= gx < width and 0 <= gy < height):
            raise ValueError(f"start {start} or goal {goal} outside the {width}x{height} grid")
        last = self._prepared_for
        if (
            last is None
            or last[0] is not multipliers
            or last[1] is not escape_multipliers
            or last[2:] != (height, width)
        ):
            tables, lo, hi, ring = _prepare(multipliers, escape_multipliers, height, width)
            self._prepared = (tables, lo, hi, np.empty(ring, dtype=np.int64))
            self._prepared_for = (multipliers, escape_multipliers, height, width)
        tables, lo, hi, heads = self._prepared
        buffers = self._buffers
        stamp = buffers.next_stamp((height, width), parent_dtype=np.int8)
        while True:
            parents = cast("npt.NDArray[np.int8]", buffers.parent)  # int8 by next_stamp
            status, cost, expansions = search(
                grid, tables, lo, hi, sx, sy, gx, gy, buffers.g, buffers.state,
                parents, buffers.heap, buffers.pool, buffers.next, heads, stamp,
            )
            if status >= 0:
                break
            buffers.grow_queue()
            stamp = buffers.next_stamp((height, width), parent_dtype=np.int8)
        if status == 0:
            log.debug("A*: no path %s -> %s after %d expansions", start, goal, expansions)
            return None
        cells = trace(parents, width, sx, sy, gx, gy)
        return CellPath(cells=cells, cost=float(cost), expansions=int(expansions))

    def closed(self, cells: npt.NDArray[np.int64]) -> npt.NDArray[np.bool_]:
        """Which ``[ix, iy]`` cells the last search closed; after a failed search, exactly the
        cells reachable from its start."""
        return self._buffers.closed(cells)


def _prepare(
    multipliers: npt.NDArray[np.float64],
    escape: npt.NDArray[np.float64] | None,
    height: int,
    width: int,
) -> tuple[npt.NDArray[np.float64], int, int, int]:
    """The kernel's 512-entry table, its escape band ``[lo, hi)`` and its bucket ring length."""
    both = np.empty(512, dtype=np.float64)
    both[:256] = multipliers
    both[256:] = multipliers if escape is None else escape
    lo = hi = 0
    if escape is not None:
        band = np.flatnonzero(np.isinf(multipliers) & np.isfinite(escape))
        if band.size:
            lo, hi = int(band[0]), int(band[-1]) + 1
    check_key_range(both, (height, width))
    finite = both[np.isfinite(both)]
    largest = float(finite.max()) if finite.size else 1.0
    # Buckets a child's f can reach beyond its parent's, plus slack for rounding.
    span = int(math.ceil(SQRT2 * (largest + 1.0) * 2.0 ** (32 - BUCKET_SHIFT))) + 3
    ring = 1 << max(2, (span - 1).bit_length())
    return both, lo, hi, ring


def warm_up() -> None:
    """Compile the kernels on a tiny grid, for writable and read-only cost arrays."""
    heap.warm_up()
    grid = np.zeros((4, 4), dtype=np.uint8)
    grid[1, 1] = 253
    table = step_multipliers(cost_weight=1.0)
    escape = step_multipliers(cost_weight=1.0, escape_below=254)
    planner = AStar(capacity=2)
    planner.search(grid, (0, 0), (3, 3), multipliers=table)
    frozen = grid.copy()
    frozen.flags.writeable = False
    planner.search(frozen, (1, 1), (3, 2), multipliers=table, escape_multipliers=escape)
