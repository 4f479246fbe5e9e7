"""Cost grids written as ASCII art for the planning tests, and an independent Dijkstra oracle.

``.`` FREE, ``#`` LETHAL, ``I`` INSCRIBED, ``?`` UNKNOWN, and a digit ``d`` the cost ``28 d``
(``9`` is 252, the dearest non-obstacle cost). The first text line is the top row (highest
``iy``), as in ``polynav.maps.ascii``.
"""

from __future__ import annotations

import math
import textwrap
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

from polynav.geometry import Pose2D
from polynav.maps import costs
from polynav.maps.map import MapInfo

_CHARS = {".": costs.FREE, "#": costs.LETHAL, "I": costs.INSCRIBED, "?": costs.UNKNOWN}


@dataclass(frozen=True, slots=True, eq=False)
class Grid:
    """A minimal :class:`~polynav.maps.interface.CostGrid`."""

    info: MapInfo
    costs: npt.NDArray[np.uint8]


def costs_from_ascii(text: str) -> npt.NDArray[np.uint8]:
    rows = [line.strip() for line in textwrap.dedent(text).splitlines() if line.strip()]
    values = [[_CHARS[c] if c in _CHARS else 28 * int(c) for c in row] for row in rows]
    return np.ascontiguousarray(np.array(values, dtype=np.uint8)[::-1])


_ORIGIN = Pose2D()


def grid_from_ascii(text: str, resolution: float = 1.0, origin: Pose2D = _ORIGIN) -> Grid:
    values = costs_from_ascii(text)
    height, width = values.shape
    return Grid(MapInfo(resolution=resolution, width=width, height=height, origin=origin), values)


def dijkstra_costs(
    values: npt.NDArray[np.uint8], table: npt.NDArray[np.float64], start: tuple[int, int]
) -> npt.NDArray[np.float64]:
    """Cheapest cost from ``start`` to every cell ``[iy, ix]`` under A*'s model, by scipy.

    8-connected, no corner cutting, a step costs its length times the multiplier of the cell
    entered; built edge by edge, independently of the kernel.
    """
    height, width = values.shape
    mult = table[values]
    passable = np.isfinite(mult)
    rows: list[int] = []
    cols: list[int] = []
    weights: list[float] = []
    for y in range(height):
        for x in range(width):
            if not passable[y, x] and (x, y) != start:
                continue
            for dx in (-1, 0, 1):
                for dy in (-1, 0, 1):
                    if dx == 0 and dy == 0:
                        continue
                    nx, ny = x + dx, y + dy
                    if not (0 <= nx < width and 0 <= ny < height) or not passable[ny, nx]:
                        continue
                    if dx != 0 and dy != 0 and not (passable[y, nx] and passable[ny, x]):
                        continue
                    rows.append(y * width + x)
                    cols.append(ny * width + nx)
                    step = math.sqrt(2.0) if dx != 0 and dy != 0 else 1.0
                    weights.append(step * float(mult[ny, nx]))
    graph = coo_matrix((weights, (rows, cols)), shape=(height * width, height * width)).tocsr()
    found = dijkstra(graph, directed=True, indices=start[1] * width + start[0])
    return np.asarray(found).reshape(height, width)


def touched_cells(x0: float, y0: float, x1: float, y1: float) -> set[tuple[int, int]]:
    """Cells ``(ix, iy)`` whose closed square meets the segment (cell coordinates): the
    supercover, computed by clipping the segment against each square (Liang-Barsky)."""
    out = set()
    for ix in range(math.floor(min(x0, x1)) - 1, math.floor(max(x0, x1)) + 2):
        for iy in range(math.floor(min(y0, y1)) - 1, math.floor(max(y0, y1)) + 2):
            lo, hi = 0.0, 1.0
            ok = True
            for p0, d, a, b in ((x0, x1 - x0, ix, ix + 1), (y0, y1 - y0, iy, iy + 1)):
                if d == 0.0:
                    if p0 < a or p0 > b:
                        ok = False
                    continue
                t0, t1 = (a - p0) / d, (b - p0) / d
                if t0 > t1:
                    t0, t1 = t1, t0
                lo, hi = max(lo, t0), min(hi, t1)
            if ok and lo <= hi:
                out.add((ix, iy))
    return out


def random_costs(
    rng: np.random.Generator, height: int, width: int, *, blocked: float, costly: float
) -> npt.NDArray[np.uint8]:
    """A grid with LETHAL cells, random inflation-like costs, and free cells."""
    values = np.zeros((height, width), dtype=np.uint8)
    draw = rng.random((height, width))
    values[draw < costly] = rng.integers(1, 253, size=int((draw < costly).sum()), dtype=np.uint8)
    values[draw < blocked] = costs.LETHAL
    return values
