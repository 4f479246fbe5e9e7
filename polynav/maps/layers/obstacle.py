"""The obstacle layer: what the lidar sees now, marked and cleared beam by beam.

Each beam marks the cell where it ended as LETHAL when the return lies within
``obstacle_max_range``, and clears the cells it passed through on the way (up to the hit, or up to
``raytrace_max_range`` for a beam with no return), as Nav2's ``ObstacleLayer`` does. Clearing is
what removes a person who walked away: the next beam through the cell frees it.

Range noise. A lidar return lies a few centimetres either side of the surface it hit. Left to
itself, one scan's short return marks the free cell in front of a post's face and the next
scan's longer return, passing through that cell, clears it: the cell flickers, and a gap one cell
wider than the robot opens and closes under the planner. So a return at range ``r`` clears only
the cells it has passed through *completely* before ``r - 3 sigma`` (``range_noise`` = sigma): the
few centimetres in front of a return are within the noise of the return itself, and a beam does
not take them as seen free. Only a beam passing well clear (another angle, a person gone) does.

The layer keeps its own grid: UNKNOWN (never seen), FREE (seen through) or LETHAL (seen hit). It
composes into the master with "max" semantics, except that a cell it has seen through turns an
UNKNOWN map cell FREE (Nav2 ``updateWithMax``): it never clears a map wall or a keepout.

The walk is the Amanatides & Woo traversal of :mod:`polynav.maps.raycast`, in one numba kernel
over the whole scan. Only cells whose value actually changes enter the dirty window, so a robot
standing in a static scene redraws almost nothing, and the costmap's update stays cheap.
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
from polynav.robot.interface import LaserScan

log = logging.getLogger(__name__)

_BIG = 1 << 40
# numba freezes module globals as constants, so the kernel reads the named costs.
_FREE = costs.FREE
_LETHAL = costs.LETHAL


@numba.njit(cache=True, nogil=True)
def _grow(bbox: npt.NDArray[np.int64], ix: int, iy: int) -> None:
    bbox[0] = min(bbox[0], ix)
    bbox[1] = min(bbox[1], iy)
    bbox[2] = max(bbox[2], ix + 1)
    bbox[3] = max(bbox[3], iy + 1)


@numba.njit(cache=True, nogil=True)
def trace_scan(
    grid: npt.NDArray[np.uint8],
    protect: npt.NDArray[np.uint8],
    sx: float,
    sy: float,
    angles: npt.NDArray[np.float64],
    ranges: npt.NDArray[np.float64],
    valid: npt.NDArray[np.bool_],
    mark: npt.NDArray[np.bool_],
    clear_len: npt.NDArray[np.float64],
    bbox: npt.NDArray[np.int64],
) -> None:
    """Mark and clear one scan in ``grid`` (FREE / LETHAL / UNKNOWN), in grid units.

    Args:
        grid: the layer's cells ``[iy, ix]``, changed in place.
        protect: scratch grid of zeros, same shape; zero again on return.
        sx, sy: sensor position in cells ((0, 0) is the grid's lower-left corner).
        angles: beam directions [rad] in the grid frame.
        ranges: beam lengths in cells (meaningful where ``valid``).
        valid: the beam has a return; clearing stops before its end cell.
        mark: the beam's end cell becomes LETHAL.
        clear_len: how far to clear along each beam, in cells: a cell is cleared only if the
            beam leaves it before this length.
        bbox: ``[ix0, iy0, ix1, iy1]`` grown by every cell whose value changed.
    """
    height, width = grid.shape
    n = angles.shape[0]
    # Mark first and protect the marked cells, so that a beam grazing another beam's hit
    # does not clear it (and the cell does not flip twice and dirty the window for nothing).
    for k in range(n):
        if not mark[k]:
            continue
        ex = int(math.floor(sx + ranges[k] * math.cos(angles[k])))
        ey = int(math.floor(sy + ranges[k] * math.sin(angles[k])))
        if 0 <= ex < width and 0 <= ey < height:
            protect[ey, ex] = 1
            if grid[ey, ex] != _LETHAL:
                grid[ey, ex] = _LETHAL
                _grow(bbox, ex, ey)
    ix0 = int(math.floor(sx))
    iy0 = int(math.floor(sy))
    for k in range(n):
        length = clear_len[k]
        if not length > 0.0:
            continue
        dx = math.cos(angles[k])
        dy = math.sin(angles[k])
        ex = -_BIG
        ey = -_BIG
        if valid[k]:
            ex = int(math.floor(sx + ranges[k] * dx))
            ey = int(math.floor(sy + ranges[k] * dy))
        ix = ix0
        iy = iy0
        step_x = 1 if dx > 0.0 else -1
        step_y = 1 if dy > 0.0 else -1
        if dx != 0.0:
            t_delta_x = abs(1.0 / dx)
            t_max_x = ((ix + 1.0 - sx) if dx > 0.0 else (sx - ix)) * t_delta_x
        else:
            t_delta_x = math.inf
            t_max_x = math.inf
        if dy != 0.0:
            t_delta_y = abs(1.0 / dy)
            t_max_y = ((iy + 1.0 - sy) if dy > 0.0 else (sy - iy)) * t_delta_y
        else:
            t_delta_y = math.inf
            t_max_y = math.inf
        while min(t_max_x, t_max_y) <= length:
            if ix == ex and iy == ey:
                break
            if 0 <= ix < width and 0 <= iy < height:
                if protect[iy, ix] == 0 and grid[iy, ix] != _FREE:
                    grid[iy, ix] = _FREE
                    _grow(bbox, ix, iy)
            if t_max_x < t_max_y:
                t_max_x += t_delta_x
                ix += step_x
            else:
                t_max_y += t_delta_y
                iy += step_y
    for k in range(n):
        if not mark[k]:
            continue
        ex = int(math.floor(sx + ranges[k] * math.cos(angles[k])))
        ey = int(math.floor(sy + ranges[k] * math.sin(angles[k])))
        if 0 <= ex < width and 0 <= ey < height:
            protect[ey, ex] = 0


def warm_up() -> None:
    """Compile :func:`trace_scan` on a tiny grid so the first real scan does not pay for it."""
    grid = np.full((4, 4), costs.UNKNOWN, dtype=np.uint8)
    one = np.ones(1, dtype=np.bool_)
    trace_scan(
        grid,
        np.zeros((4, 4), dtype=np.uint8),
        1.5,
        1.5,
        np.zeros(1),
        np.ones(1),
        one,
        one,
        np.ones(1),
        np.array([_BIG, _BIG, -_BIG, -_BIG], dtype=np.int64),
    )


class ObstacleLayer:
    """Obstacles seen by the lidar, kept until a later beam sees through them."""

    def __init__(
        self,
        info: MapInfo,
        *,
        obstacle_max_range: float,
        raytrace_max_range: float,
        range_noise: float = 0.01,
    ) -> None:
        """Args: the grid geometry, the marking and clearing ranges [m], and the standard
        deviation [m] of the lidar's range noise (see the module docstring)."""
        self._info = info
        self._clear_margin = 3.0 * range_noise
        self._obstacle_max_range = obstacle_max_range
        self._raytrace_max_range = raytrace_max_range
        self._grid = np.full((info.height, info.width), costs.UNKNOWN, dtype=np.uint8)
        self._protect = np.zeros((info.height, info.width), dtype=np.uint8)
        self._pending: Window | None = None
        self._touched: Window | None = None
        self._passable: npt.NDArray[np.bool_] | None = None

    @property
    def grid(self) -> npt.NDArray[np.uint8]:
        """The layer's cells ``[iy, ix]``: UNKNOWN, FREE or LETHAL (read them, do not write)."""
        return self._grid

    def add_scan(self, pose: Pose2D, scan: LaserScan) -> Window | None:
        """Mark and clear along every beam of ``scan`` taken with the robot at ``pose``.

        A beam's world angle is ``pose.theta + scan.sensor_pose.theta + angle``. Ranges that are
        not finite, NaN, below ``range_min`` or above ``range_max`` are no-returns: they mark
        nothing and clear up to ``min(raytrace_max_range, range_max)`` (the sensor cannot have
        seen free space beyond its own range). A return clears up to the cell it hit, or up to
        ``raytrace_max_range``, and marks that cell if it is nearer than ``obstacle_max_range``.

        Returns:
            The window of cells whose value changed (``None`` if none did).
        """
        info = self._info
        sensor = pose.compose(scan.sensor_pose)
        # Work in the grid frame, in cells: (0, 0) is the lower-left corner of cell (0, 0).
        lx, ly = info.origin.inverse().transform_point(sensor.x, sensor.y)
        res = info.resolution
        angles = scan.angles.astype(np.float64) + (sensor.theta - info.origin.theta)
        ranges = np.asarray(scan.ranges, dtype=np.float64)
        with np.errstate(invalid="ignore"):
            valid = np.isfinite(ranges) & (ranges >= scan.range_min) & (ranges <= scan.range_max)
        mark = valid & (ranges < self._obstacle_max_range)
        if self._passable is not None:
            mark &= ~self._ends_in(self._passable, lx, ly, angles, ranges, valid)
        no_return = min(self._raytrace_max_range, scan.range_max)
        clear_len = np.where(
            valid,
            np.minimum(ranges - self._clear_margin, self._raytrace_max_range),
            no_return,
        )
        bbox = np.array([_BIG, _BIG, -_BIG, -_BIG], dtype=np.int64)
        trace_scan(
            self._grid,
            self._protect,
            lx / res,
            ly / res,
            np.ascontiguousarray(angles),
            np.where(valid, ranges, 0.0) / res,
            valid,
            mark,
            clear_len / res,
            bbox,
        )
        changed: Window | None = None
        if bbox[0] < bbox[2]:
            changed = (int(bbox[0]), int(bbox[1]), int(bbox[2]), int(bbox[3]))
        self._pending = win.union(self._pending, changed)
        self._touched = win.union(self._touched, changed)
        return changed

    def set_passable(self, passable: npt.NDArray[np.bool_] | None) -> Window | None:
        """Cells ``[iy, ix]`` the lidar never marks (``None``: none): the leaves of doors the
        robot opens on its way. A closed door is passable to the planner, or no route would
        cross it; the robot waits before it until it is open (:mod:`polynav.runtime.
        door_passage`). Marks already in those cells are forgotten. Returns the window of
        cells dirtied (``None`` if none)."""
        if passable is not None and passable.shape != self._grid.shape:
            raise ValueError(f"passable mask {passable.shape} != grid {self._grid.shape}")
        self._passable = passable
        if passable is None:
            return None
        forget = passable & (self._grid == costs.LETHAL)
        if not forget.any():
            return None
        self._grid[forget] = costs.UNKNOWN
        iy, ix = np.nonzero(forget)
        window = (int(ix.min()), int(iy.min()), int(ix.max()) + 1, int(iy.max()) + 1)
        self._pending = win.union(self._pending, window)
        return window

    def _ends_in(self, mask: npt.NDArray[np.bool_], lx: float, ly: float,
                 angles: npt.NDArray[np.float64], ranges: npt.NDArray[np.float64],
                 valid: npt.NDArray[np.bool_]) -> npt.NDArray[np.bool_]:
        """Per beam: its return lies in a cell of ``mask`` (grid frame, metres from the
        grid's corner)."""
        res = self._info.resolution
        r = np.where(valid, ranges, 0.0)
        ix = np.floor((lx + r * np.cos(angles)) / res).astype(np.int64)
        iy = np.floor((ly + r * np.sin(angles)) / res).astype(np.int64)
        height, width = mask.shape
        inside = valid & (ix >= 0) & (iy >= 0) & (ix < width) & (iy < height)
        out = np.zeros(len(ranges), dtype=np.bool_)
        out[inside] = mask[iy[inside], ix[inside]]
        return out

    def clear(self) -> None:
        """Forget every observation (the "clear costmap" recovery)."""
        if self._touched is not None:
            self._grid[win.slices(self._touched)] = costs.UNKNOWN
        self._pending = win.union(self._pending, self._touched)
        self._touched = None

    def clear_around(self, x: float, y: float, radius: float) -> Window | None:
        """Forget what was seen within ``radius`` [m] of world point (x, y).

        The first rung of the recovery ladder: marks around a blocked robot (stale ones, noise,
        a person gone) are dropped, and the next scans mark again what is really there; what is
        farther away is kept, so the planner does not forget the rest of the field.
        Returns the window of cells dirtied (``None`` if none).
        """
        info = self._info
        res = info.resolution
        cx, cy = info.world_to_cell(x, y)
        reach = int(math.ceil(radius / res))
        window = win.clip((cx - reach, cy - reach, cx + reach + 1, cy + reach + 1), info.width,
                          info.height)
        if window is None:
            return None
        region = win.slices(window)
        iy, ix = np.mgrid[region]
        centres = info.cells_to_world(np.column_stack((ix.ravel(), iy.ravel())))
        near = (np.hypot(centres[:, 0] - x, centres[:, 1] - y) <= radius).reshape(ix.shape)
        cells = self._grid[region]
        near &= cells != costs.UNKNOWN
        if not near.any():
            return None
        cells[near] = costs.UNKNOWN
        self._pending = win.union(self._pending, window)
        return window

    def update_bounds(self, pose: Pose2D, window: Window | None) -> Window | None:
        pending, self._pending = self._pending, None
        return win.union(window, pending)

    def update_costs(self, master: npt.NDArray[np.uint8], window: Window) -> None:
        region = win.slices(window)
        layer = self._grid[region]
        out = master[region]
        out[layer == costs.LETHAL] = costs.LETHAL
        out[(layer == costs.FREE) & (out == costs.UNKNOWN)] = costs.FREE
