"""A growing log-odds occupancy grid, and the ray insertion of a scan into it.

Each scan lowers the log-odds of the cells its beams cross (a *miss*) and raises the cell each
beam ends in (a *hit*), the inverse sensor model of Probabilistic Robotics §9.2. Within one
scan a cell is updated at most once, hits first, so a wall cell grazed by a neighbouring beam
is not cleared by the same scan that sees it (Cartographer's update markers).

The grid grows in whole blocks when a scan reaches past its edge, so a submap never needs to
know its extent in advance. Cells are indexed ``[iy, ix]``; ``origin`` is the position of the
lower-left corner of cell (0, 0) in the grid's frame (never rotated).
"""

from __future__ import annotations

import math

import numba
import numpy as np
import numpy.typing as npt

from polynav.geometry import Pose2D
from polynav.maps.map import FREE, OCCUPIED, UNKNOWN, Map, MapInfo

# Growth step [cells]: fewer reallocations than growing to the exact need.
_BLOCK = 64
# Log-odds clamp: a cell seen often stays revisable by a few contrary scans.
_CLAMP = 4.0


def log_odds(p: float) -> float:
    return math.log(p / (1.0 - p))


class LogOddsGrid:
    """Log-odds occupancy in a frame of its own, growing as scans are inserted.

    Args:
        resolution: cell size [m].
        hit: log-odds added to a cell a beam ends in.
        miss: log-odds added (negative) to a cell a beam crosses.
        lattice: a corner of the unbounded cell lattice [m] (cells are
            ``[lattice + i * resolution, lattice + (i + 1) * resolution)``); an existing map's
            origin, so a grid seeded from it (:meth:`seeded`) keeps its cells where they were.
    """

    def __init__(self, resolution: float, *, hit: float, miss: float,
                 lattice: tuple[float, float] = (0.0, 0.0)) -> None:
        self.resolution = resolution
        self.hit = hit
        self.miss = miss
        self.lattice = lattice
        self.values = np.zeros((0, 0), dtype=np.float32)
        self._marks = np.zeros((0, 0), dtype=np.int32)
        self._stamp = 0
        self.ox = 0  # cell index of the grid's (0, 0) in the unbounded lattice
        self.oy = 0

    @classmethod
    def seeded(cls, grid: Map, *, hit: float, miss: float, level: float) -> LogOddsGrid:
        """A grid holding an existing map: occupied cells at ``+level``, free ones at
        ``-level``, unknown at 0 (a saved map kept no log-odds; ``level`` says how many
        contrary scans it takes to revise a cell, so a moved table is redrawn when updating).

        Raises:
            ValueError: the map's origin is rotated (a grid here is never rotated).
        """
        info = grid.info
        if abs(math.remainder(info.origin.theta, 2.0 * math.pi)) > 1e-9:
            raise ValueError("a map with a rotated origin cannot seed a log-odds grid")
        out = cls(info.resolution, hit=hit, miss=miss, lattice=(info.origin.x, info.origin.y))
        data = grid.data
        values = np.zeros((info.height, info.width), dtype=np.float32)
        values[(data >= FREE) & (data <= 20)] = -level  # map_saver's free threshold 0.196
        values[data >= 65] = level  # and its occupied one
        out.values = values
        out._marks = np.zeros((info.height, info.width), dtype=np.int32)
        return out

    @property
    def origin_xy(self) -> tuple[float, float]:
        """Position [m] of the lower-left corner of cell (0, 0), grid frame."""
        return (self.lattice[0] + self.ox * self.resolution,
                self.lattice[1] + self.oy * self.resolution)

    def insert(self, pose: Pose2D, points: npt.NDArray[np.float64],
               sensor: npt.NDArray[np.float64]) -> None:
        """Insert one scan.

        Args:
            pose: the robot's pose in the grid's frame.
            points: (N, 2) endpoints [m] in the robot frame.
            sensor: (2,) the sensor's position [m] in the robot frame (where the rays start).
        """
        if points.shape[0] == 0:
            return
        c, s = math.cos(pose.theta), math.sin(pose.theta)
        gx = pose.x + c * points[:, 0] - s * points[:, 1]
        gy = pose.y + s * points[:, 0] + c * points[:, 1]
        sx = pose.x + c * sensor[0] - s * sensor[1] - self.lattice[0]
        sy = pose.y + s * sensor[0] + c * sensor[1] - self.lattice[1]
        gx -= self.lattice[0]
        gy -= self.lattice[1]
        inv = 1.0 / self.resolution
        cx = np.floor(gx * inv).astype(np.int64)
        cy = np.floor(gy * inv).astype(np.int64)
        scx = math.floor(sx * inv)
        scy = math.floor(sy * inv)
        self._grow(min(int(cx.min()), scx), min(int(cy.min()), scy),
                   max(int(cx.max()), scx), max(int(cy.max()), scy))
        self._stamp += 1
        _insert(self.values, self._marks, self._stamp, cx - self.ox, cy - self.oy,
                scx - self.ox, scy - self.oy, self.hit, self.miss, _CLAMP)

    def _grow(self, x0: int, y0: int, x1: int, y1: int) -> None:
        h, w = self.values.shape
        if h and x0 >= self.ox and y0 >= self.oy and x1 < self.ox + w and y1 < self.oy + h:
            return
        if not h:
            nx0, ny0, nx1, ny1 = x0 - _BLOCK, y0 - _BLOCK, x1 + _BLOCK, y1 + _BLOCK
        else:
            nx0 = min(self.ox, x0 - _BLOCK if x0 < self.ox else self.ox)
            ny0 = min(self.oy, y0 - _BLOCK if y0 < self.oy else self.oy)
            nx1 = max(self.ox + w - 1, x1 + _BLOCK if x1 >= self.ox + w else self.ox + w - 1)
            ny1 = max(self.oy + h - 1, y1 + _BLOCK if y1 >= self.oy + h else self.oy + h - 1)
        values = np.zeros((ny1 - ny0 + 1, nx1 - nx0 + 1), dtype=np.float32)
        marks = np.zeros(values.shape, dtype=np.int32)
        if h:
            values[self.oy - ny0:self.oy - ny0 + h, self.ox - nx0:self.ox - nx0 + w] = self.values
            marks[self.oy - ny0:self.oy - ny0 + h, self.ox - nx0:self.ox - nx0 + w] = self._marks
        self.values, self._marks = values, marks
        self.ox, self.oy = nx0, ny0

    def to_map(self, *, occupied: float, free: float, frame: Pose2D | None = None) -> Map:
        """The grid as a polynav :class:`Map` (100 occupied, 0 free, -1 unknown).

        Args:
            occupied: log-odds at or above which a cell is occupied.
            free: log-odds at or below which a cell is free.
            frame: the grid frame's pose in the map's parent frame (an unrotated grid stays
                unrotated only when ``frame.theta`` is 0).
        """
        data = np.full(self.values.shape, UNKNOWN, dtype=np.int8)
        data[self.values <= free] = FREE
        data[self.values >= occupied] = OCCUPIED
        h, w = data.shape
        x, y = self.origin_xy
        origin = Pose2D(x, y, 0.0) if frame is None else frame.compose(Pose2D(x, y, 0.0))
        info = MapInfo(self.resolution, w, h, origin)
        return Map(info, data)


@numba.njit(cache=True, nogil=True)
def _insert(values: npt.NDArray[np.float32], marks: npt.NDArray[np.int32], stamp: int,
            cx: npt.NDArray[np.int64], cy: npt.NDArray[np.int64], sx: int, sy: int,
            hit: float, miss: float, clamp: float) -> None:
    for k in range(cx.shape[0]):
        x, y = cx[k], cy[k]
        if marks[y, x] != stamp:
            marks[y, x] = stamp
            values[y, x] = min(values[y, x] + hit, clamp)
    for k in range(cx.shape[0]):
        # Bresenham from the sensor cell to the endpoint cell, the endpoint excluded.
        x, y = sx, sy
        ex, ey = cx[k], cy[k]
        dx = abs(ex - x)
        dy = -abs(ey - y)
        stx = 1 if x < ex else -1
        sty = 1 if y < ey else -1
        err = dx + dy
        while x != ex or y != ey:
            if marks[y, x] != stamp:
                marks[y, x] = stamp
                values[y, x] = max(values[y, x] + miss, -clamp)
            e2 = 2 * err
            if e2 >= dy:
                err += dy
                x += stx
            if e2 <= dx:
                err += dx
                y += sty


def warm_up() -> None:
    """Compile the insertion kernel on a tiny scan."""
    grid = LogOddsGrid(0.05, hit=0.8, miss=-0.4)
    grid.insert(Pose2D(), np.array([[0.3, 0.1]]), np.zeros(2))
