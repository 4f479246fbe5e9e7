"""What the grid searches share: the step-cost table, reusable buffers and the result value.

A cost grid is ``costs[iy, ix]`` (uint8, Nav2 values, ``polynav.maps.costs``). A search turns each
value into a *step multiplier* through a 256-entry table (:func:`step_multipliers`): entering a
cell of cost ``c`` costs ``step * (1 + cost_weight * c / 252)``, with ``step`` 1 or sqrt 2 [cells],
and an infinite multiplier marks an impassable cell. As every multiplier is at least 1, the
distance heuristics stay admissible.

:class:`SearchBuffers` keeps per-grid-size scratch arrays across queries. A *generation stamp*
marks which entries belong to the current query, so a query touches only the cells it visits
instead of re-initialising ``O(H * W)`` memory: on a 2000 x 2000 map that initialisation alone
would cost more than a typical search.
"""

from __future__ import annotations

import functools
import logging
import math
from dataclasses import dataclass
from typing import Protocol

import numpy as np
import numpy.typing as npt

from polynav.maps import costs as cost_values
from polynav.planning.heap import MAX_F

log = logging.getLogger(__name__)

_STAMP_LIMIT = 2**31 - 4


@dataclass(frozen=True, slots=True, eq=False)
class CellPath:
    """A path found on a cost grid.

    Attributes:
        cells: (N, 2) int64 array of ``[ix, iy]``, start first, goal last; ``N >= 1`` (a single
            cell when start and goal coincide). Consecutive cells are grid neighbours for A*,
            and any-angle vertices for Theta*.
        cost: the search's cost of the path [cells]: step lengths times step multipliers.
        expansions: how many cells the search closed (a measure of work, for benchmarks).
    """

    cells: npt.NDArray[np.int64]
    cost: float
    expansions: int


class GridSearch(Protocol):
    """A shortest-path search on a cost grid (A*, Theta*), reusing its buffers across queries."""

    def search(
        self,
        costs: npt.NDArray[np.uint8],
        start: tuple[int, int],
        goal: tuple[int, int],
        *,
        multipliers: npt.NDArray[np.float64],
        escape_multipliers: npt.NDArray[np.float64] | None = None,
    ) -> CellPath | None:
        """The cheapest path from ``start`` to ``goal`` (cells ``(ix, iy)``), or None."""
        ...

    def closed(self, cells: npt.NDArray[np.int64]) -> npt.NDArray[np.bool_]:
        """Which of the (N, 2) ``[ix, iy]`` cells the last search closed."""
        ...


@functools.lru_cache(maxsize=64)
def step_multipliers(
    *,
    cost_weight: float,
    lethal_threshold: int = cost_values.INSCRIBED,
    unknown_cost: int | None = None,
    escape_below: int | None = None,
) -> npt.NDArray[np.float64]:
    """The 256-entry table from cell cost to step multiplier (module docstring).

    Args:
        cost_weight: how much a cost of 252 multiplies a step beyond 1 (0 ignores costs).
        lethal_threshold: cells with cost at or above this are impassable (``inf``).
        unknown_cost: if given, UNKNOWN cells are passable and priced as this cost (which must
            be below ``lethal_threshold``); otherwise UNKNOWN follows ``lethal_threshold``.
        escape_below: if given, cells with ``lethal_threshold <= cost < escape_below`` become
            passable too. This is the table a search uses while leaving a start region of
            inscribed cells (see ``astar.search``).

    Returns:
        A read-only float64 array of 256 multipliers, each ``>= 1`` or ``inf``.

    Raises:
        ValueError: a negative or infinite weight, a threshold outside 1..256, or an unknown
            cost at or above the threshold.
    """
    if not (cost_weight >= 0.0 and math.isfinite(cost_weight)):
        raise ValueError(f"cost_weight must be finite and >= 0, got {cost_weight}")
    if not 1 <= lethal_threshold <= 256:
        raise ValueError(f"lethal_threshold must be within 1..256, got {lethal_threshold}")
    values = np.arange(256, dtype=np.float64)
    table = 1.0 + cost_weight * values / cost_values.MAX_NON_OBSTACLE
    passable_below = lethal_threshold if escape_below is None else max(escape_below,
                                                                       lethal_threshold)
    table[passable_below:] = np.inf
    if unknown_cost is not None:
        if not 0 <= unknown_cost < lethal_threshold:
            raise ValueError(f"unknown_cost {unknown_cost} must be below the lethal threshold")
        table[cost_values.UNKNOWN] = 1.0 + cost_weight * unknown_cost / cost_values.MAX_NON_OBSTACLE
    table.flags.writeable = False
    return table


def check_key_range(multipliers: npt.NDArray[np.float64], shape: tuple[int, int]) -> None:
    """Refuse a grid and table whose path costs could overflow the open-list keys.

    Raises:
        ValueError: the dearest possible path (every cell at the largest finite multiplier)
            could reach ``heap.MAX_F``.
    """
    finite = multipliers[np.isfinite(multipliers)]
    largest = float(finite.max()) if finite.size else 1.0
    height, width = shape
    if largest * math.sqrt(2.0) * height * width + height + width >= MAX_F:
        raise ValueError("step multipliers too large for this grid's open-list keys")


class SearchBuffers:
    """Scratch arrays for one grid size, reused across queries with a generation stamp.

    ``state[cell]`` equals ``stamp`` when the cell is open in the current query and ``stamp + 1``
    when it is closed (a search may use a few more values, up to its stride); any other value
    means "not seen", whatever ``g`` holds. The stamp grows by the stride per query, and the
    arrays are cleared only when it would overflow.

    The open list lives in ``heap`` (two int64 words per entry, see ``heap``) and, for A*'s
    bucket queue, in ``pool``/``next`` (entries of later buckets, chained per bucket). Their
    capacity defaults to one entry per cell plus slack: after dropping stale entries at most one
    live entry per open cell remains, so a search never runs out.

    Args:
        capacity: open-list entries to allocate instead of the default (tests use a small one to
            exercise compaction and growth).
    """

    def __init__(self, capacity: int | None = None) -> None:
        self._capacity_override = capacity
        self.shape: tuple[int, int] = (0, 0)
        self.capacity = 0
        self.g = np.empty(0, dtype=np.float64)
        self.state = np.zeros(0, dtype=np.int32)
        self.parent: npt.NDArray[np.generic] = np.empty(0, dtype=np.int8)
        self.heap = np.empty(0, dtype=np.int64)
        self.pool = np.empty(0, dtype=np.int64)
        self.next = np.empty(0, dtype=np.int64)
        self.stamp = 0

    def next_stamp(
        self, shape: tuple[int, int], *, parent_dtype: type[np.generic], stride: int = 2
    ) -> int:
        """Make the buffers fit ``shape`` and return the stamp of a new query.

        ``stride`` is how many state values a query may use from its stamp on (2: open and
        closed; Theta* uses 4); the stamp is a multiple of it.
        """
        if shape != self.shape or self.parent.dtype != parent_dtype:
            cells = shape[0] * shape[1]
            if cells >= 2**31:
                raise ValueError(f"grid of {cells} cells is too large (limit 2**31)")
            log.debug("search buffers for a %dx%d grid", shape[1], shape[0])
            self.shape = shape
            # np.empty does not touch the pages: a search only commits the memory it visits.
            self.g = np.empty(cells, dtype=np.float64)
            self.state = np.zeros(cells, dtype=np.int32)
            self.parent = np.empty(cells, dtype=parent_dtype)
            capacity = self._capacity_override or cells + 8
            self._allocate_queue(capacity)
            self.stamp = 0
        self.stamp += stride - self.stamp % stride
        if self.stamp >= _STAMP_LIMIT:
            self.state.fill(0)
            self.stamp = stride
        return self.stamp

    def grow_queue(self) -> None:
        """Double the open-list capacity (a search reported it full even after compaction)."""
        log.debug("open list grows to %d entries", 2 * self.capacity)
        self._allocate_queue(2 * self.capacity)

    def _allocate_queue(self, capacity: int) -> None:
        self.capacity = capacity
        self.heap = np.empty(2 * capacity, dtype=np.int64)
        self.pool = np.empty(2 * capacity, dtype=np.int64)
        self.next = np.empty(capacity, dtype=np.int64)

    def closed(self, cells: npt.NDArray[np.int64]) -> npt.NDArray[np.bool_]:
        """Which ``[ix, iy]`` cells the last query closed (all False before any query)."""
        pts = np.asarray(cells, dtype=np.int64).reshape(-1, 2)
        if self.stamp == 0:
            return np.zeros(pts.shape[0], dtype=bool)
        flat = pts[:, 1] * self.shape[1] + pts[:, 0]
        return np.asarray(self.state[flat] == self.stamp + 1)
