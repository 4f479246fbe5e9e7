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
def _squared_distances(lethal: npt.NDArray[np.bool_], out: npt.NDArray[np.int64]) -> None:
    height, width = lethal.shape
    # Farther than any cell of the grid can be: stands for "no lethal cell in this column".
    far = height + width
    g = np.empty((height, width), dtype=np.int64)
    for x in range(width):
        d = far
        for y in range(height):
            d = 0 if lethal[y, x] else min(d + 1, far)
            g[y, x] = d
        d = far
        for y in range(height - 1, -1, -1):
            d = 0 if lethal[y, x] else min(d + 1, far)
            g[y, x] = min(g[y, x], d)
    # Per row, the lower envelope of the parabolas (x - q)^2 + g(q)^2.
    v = np.empty(width, dtype=np.int64)
    z = np.empty(width + 1, dtype=np.float64)
    f = np.empty(width, dtype=np.int64)
    for y in range(height):
        for q in range(width):
            f[q] = g[y, q] * g[y, q]
        k = 0
        v[0] = 0
        z[0] = -np.inf
        z[1] = np.inf
        for q in range(1, width):
            s = ((f[q] + q * q) - (f[v[k]] + v[k] * v[k])) / (2.0 * (q - v[k]))
            while s <= z[k]:
                k -= 1
                s = ((f[q] + q * q) - (f[v[k]] + v[k] * v[k])) / (2.0 * (q - v[k]))
            k += 1
            v[k] = q
            z[k] = s
            z[k + 1] = np.inf
        k = 0
        for q in range(width):
            while z[k + 1] < q:
                k += 1
            out[y, q] = (q - v[k]) * (q - v[k]) + f[v[k]]


def squared_distances(lethal: npt.NDArray[np.bool_]) -> npt.NDArray[np.int64]:
    """Squared distance [cells^2] from each cell centre to the nearest ``True`` cell's centre.

    Where there is no ``True`` cell at all, the values are at least ``(height + width)^2``.
    """
    out = np.empty(lethal.shape, dtype=np.int64)
    _squared_distances(np.ascontiguousarray(lethal, dtype=np.bool_), out)
    return out


def warm_up() -> None:
    """Compile the distance-transform kernel on a tiny grid."""
    squared_distances(np.eye(3, dtype=np.bool_))


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
        lethal = master[win.slices(read)] == costs.LETHAL
        if not lethal.any():
            return
        # The part of the read window that is the write window.
        inner = (
            slice(window[1] - read[1], window[3] - read[1]),
            slice(window[0] - read[0], window[2] - read[0]),
        )
        d2 = squared_distances(lethal)[inner]
        np.minimum(d2, self._table.shape[0] - 1, out=d2)
        out = master[win.slices(window)]
        np.maximum(out, self._table[d2], out=out)
