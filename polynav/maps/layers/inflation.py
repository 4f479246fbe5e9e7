"""The inflation layer: costs that fall off with distance from the nearest lethal cell.

A planner treats the robot as a point, so every obstacle is grown by the robot's inscribed radius
(INSCRIBED: the robot centred here would touch it) and then by a decaying cost up to
``inflation_radius`` that keeps paths away from walls when there is room (Nav2
``InflationLayer::computeCost``):

* distance 0 (the obstacle itself): LETHAL;
* distance <= ``robot_radius``: INSCRIBED (253);
* distance <= ``inflation_radius``: ``int(252 * exp(-cost_scaling_factor * (d - robot_radius)))``;
* beyond: FREE.

Distances are between cell centres: an exact Euclidean distance transform over the dirty window
grown by the inflation radius (a lethal cell outside the window can still inflate a cell inside
it). It is Felzenszwalb & Huttenlocher's two-pass squared transform ("Distance Transforms of
Sampled Functions", Theory of Computing 2012) in a numba kernel: it gives the same distances as
``scipy.ndimage.distance_transform_edt`` (the tests check this) at several times the speed, which
is most of the cost of a scan update. The squared distance in cells is an integer, so the cost is
a table lookup, exact and the same for every call. Inflation takes the maximum with what the
layers below wrote: it never lowers a cost, and UNKNOWN (255, the largest value) stays UNKNOWN.

Lethal cells are stable under inflation (only a lethal cell gets distance 0), so reading them from
the master outside the window, where the previous inflation already ran, is safe.
"""

from __future__ import annotations

import logging
import math

import numba
import numpy as np
import numpy.typing as npt

from polynav.geometry import Pose2D
from polynav.maps import costs
from polynav.maps.interface import Window
from polynav.maps.layers import window as win
from polynav.maps.map import MapInfo

log = logging.getLogger(__name__)

# Distances within this of a threshold count as on it, so 11 cells of 0.05 m is 0.55 m.
_EPS = 1e-9
_LETHAL = np.uint8(costs.LETHAL)


def inflation_cost(
    distance: float, *, robot_radius: float, inflation_radius: float, cost_scaling_factor: float
) -> int:
    """Cost of a cell ``distance`` [m] from the nearest lethal cell (module docstring)."""
    if distance <= 0.0:
        return costs.LETHAL
    if distance <= robot_radius + _EPS:
        return costs.INSCRIBED
    if distance <= inflation_radius + _EPS:
        factor = math.exp(-cost_scaling_factor * (distance - robot_radius))
        return int((costs.INSCRIBED - 1) * factor)
    return costs.FREE


@numba.njit(cache=True, nogil=True)
def _envelope(f: npt.NDArray[np.int64], v: npt.NDArray[np.int64],
              z: npt.NDArray[np.float64]) -> None:
    """The lower envelope of the parabolas (x - q)^2 + f[q] (its vertices ``v``, bounds ``z``)."""
    k = 0
    v[0] = 0
    z[0] = -np.inf
    z[1] = np.inf
    for q in range(1, f.shape[0]):
        s = ((f[q] + q * q) - (f[v[k]] + v[k] * v[k])) / (2.0 * (q - v[k]))
        while s <= z[k]:
            k -= 1
            s = ((f[q] + q * q) - (f[v[k]] + v[k] * v[k])) / (2.0 * (q - v[k]))
        k += 1
        v[k] = q
        z[k] = s
        z[k + 1] = np.inf


@numba.njit(cache=True, nogil=True)
def _column_pass(lethal: npt.NDArray[np.bool_], g: npt.NDArray[np.int64]) -> bool:
    """Distance along each column to the nearest lethal cell (``height + width``: none);
    whether there is a lethal cell at all. Row by row, so memory is read in order."""
    height, width = lethal.shape
    far = height + width
    found = False
    for x in range(width):
        found |= lethal[0, x]
        g[0, x] = 0 if lethal[0, x] else far
    for y in range(1, height):
        for x in range(width):
            found |= lethal[y, x]
            g[y, x] = 0 if lethal[y, x] else min(g[y - 1, x] + 1, far)
    for y in range(height - 2, -1, -1):
        for x in range(width):
            g[y, x] = min(g[y, x], g[y + 1, x] + 1)
    return found


@numba.njit(cache=True, nogil=True)
def _squared_distances(lethal: npt.NDArray[np.bool_], out: npt.NDArray[np.int64]) -> None:
    height, width = lethal.shape
    g = np.empty((height, width), dtype=np.int64)
    _column_pass(lethal, g)
    v = np.empty(width, dtype=np.int64)
    z = np.empty(width + 1, dtype=np.float64)
    f = np.empty(width, dtype=np.int64)
    for y in range(height):
        for q in range(width):
            f[q] = g[y, q] * g[y, q]
        _envelope(f, v, z)
        k = 0
        for q in range(width):
            while z[k + 1] < q:
                k += 1
            out[y, q] = (q - v[k]) * (q - v[k]) + f[v[k]]


@numba.njit(cache=True, nogil=True)
def _inflate(master: npt.NDArray[np.uint8], table: npt.NDArray[np.uint8],
             read: tuple[int, int, int, int], write: tuple[int, int, int, int]) -> None:
    """Raise ``master`` in the ``write`` window to the inflation cost of its distance to the
    nearest lethal cell of the ``read`` window (which holds every lethal cell that can reach
    it). Only the write window's rows need the second pass, and only its cells are written."""
    lethal = master[read[1]:read[3], read[0]:read[2]] == _LETHAL
    height, width = lethal.shape
    g = np.empty((height, width), dtype=np.int64)
    if not _column_pass(lethal, g):
        return
    last = table.shape[0] - 1
    v = np.empty(width, dtype=np.int64)
    z = np.empty(width + 1, dtype=np.float64)
    f = np.empty(width, dtype=np.int64)
    q0, q1 = write[0] - read[0], write[2] - read[0]
    for y in range(write[1] - read[1], write[3] - read[1]):
        nearest = last
        for q in range(width):
            f[q] = g[y, q] * g[y, q]
            nearest = min(nearest, f[q])
        if nearest >= last:
            continue  # no lethal cell within reach of this row: every cost stays
        _envelope(f, v, z)
        k = 0
        row = master[read[1] + y]
        for q in range(q0, q1):
            while z[k + 1] < q:
                k += 1
            d2 = (q - v[k]) * (q - v[k]) + f[v[k]]
            row[read[0] + q] = max(row[read[0] + q], table[min(d2, last)])


def squared_distances(lethal: npt.NDArray[np.bool_]) -> npt.NDArray[np.int64]:
    """Squared distance [cells^2] from each cell centre to the nearest ``True`` cell's centre.

    Where there is no ``True`` cell at all, the values are at least ``(height + width)^2``.
    The same two passes the inflation kernel runs window by window, over a whole grid: the
    layer does not call it, the tests check it against scipy's transform.
    """
    out = np.empty(lethal.shape, dtype=np.int64)
    _squared_distances(np.ascontiguousarray(lethal, dtype=np.bool_), out)
    return out


def warm_up() -> None:
    """Compile the inflation kernel on a tiny grid."""
    grid = np.zeros((3, 3), dtype=np.uint8)
    grid[1, 1] = costs.LETHAL
    _inflate(grid, np.array([costs.LETHAL, 0], dtype=np.uint8), (0, 0, 3, 3), (0, 0, 3, 3))


class InflationLayer:
    """Inflates every lethal cell of the master by the robot radius and a decaying cost."""

    def __init__(
        self,
        info: MapInfo,
        *,
        robot_radius: float,
        inflation_radius: float,
        cost_scaling_factor: float,
    ) -> None:
        self._info = info
        res = info.resolution
        # No cell farther than this many cells from a lethal cell gets a cost.
        self._cells = max(int(math.ceil(inflation_radius / res - _EPS)), 0)
        n2 = self._cells * self._cells
        # Indexed by squared distance in cells; the last entry (FREE) stands for "farther".
        self._table = np.array(
            [
                inflation_cost(
                    math.sqrt(d2) * res,
                    robot_radius=robot_radius,
                    inflation_radius=inflation_radius,
                    cost_scaling_factor=cost_scaling_factor,
                )
                for d2 in range(n2 + 2)
            ],
            dtype=np.uint8,
        )
        self._table[-1] = costs.FREE

    @property
    def cell_radius(self) -> int:
        """How far [cells] a lethal cell can raise costs."""
        return self._cells

    def update_bounds(self, pose: Pose2D, window: Window | None) -> Window | None:
        if window is None:
            return None
        return win.grow(window, self._cells, self._info.width, self._info.height)

    def update_costs(self, master: npt.NDArray[np.uint8], window: Window) -> None:
        if self._cells == 0:
            return
        read = win.grow(window, self._cells, self._info.width, self._info.height)
        _inflate(master, self._table, read, window)
