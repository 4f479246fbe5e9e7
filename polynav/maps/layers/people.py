"""The people layer: a social cost around where people are and will shortly be.

Between the obstacle layer and inflation. The lidar already marks a person's legs as an
obstacle; this layer adds a soft, non-lethal cost within the social distance of each person's
current and predicted positions, so plans pass people at a distance where there is room and
do not plan into where a walker is heading. Being soft, it never makes a goal unreachable on its
own: a way that only people block is the navigator's to wait for.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

from polynav.geometry import Pose2D
from polynav.maps.interface import Window
from polynav.maps.layers import window as win
from polynav.maps.map import MapInfo

log = logging.getLogger(__name__)


class PeopleLayer:
    """Discs of ``radius`` [m] around given positions, at ``cost`` (1..252)."""

    def __init__(self, info: MapInfo, *, radius: float, cost: int) -> None:
        self._info = info
        self._radius = radius
        self._cost = np.uint8(cost)
        self._mask = np.zeros((info.height, info.width), dtype=np.bool_)
        self._drawn: Window | None = None
        self._pending: Window | None = None
        r = int(math.ceil(radius / info.resolution))
        offsets = np.arange(-r, r + 1)
        dx, dy = np.meshgrid(offsets, offsets)
        self._disc: npt.NDArray[np.bool_] = (dx * dx + dy * dy) * info.resolution**2 <= radius**2
        self._r = r

    @property
    def mask(self) -> npt.NDArray[np.bool_]:
        """Cells ``[iy, ix]`` under the social cost (read them, do not write)."""
        return self._mask

    def set_people(self, positions: Sequence[tuple[float, float]]) -> None:
        """Replace the positions; the old and the new discs are redrawn at the next update."""
        if self._drawn is None and not positions:
            return
        if self._drawn is not None:
            self._mask[win.slices(self._drawn)] = False
        drawn: Window | None = None
        info, r, height, width = self._info, self._r, self._info.height, self._info.width
        for x, y in positions:
            if not (math.isfinite(x) and math.isfinite(y)):
                continue
            ix, iy = info.world_to_cell(x, y)
            box = win.clip((ix - r, iy - r, ix + r + 1, iy + r + 1), width, height)
            if box is None:
                continue
            disc = self._disc[box[1] - (iy - r): box[3] - (iy - r),
                              box[0] - (ix - r): box[2] - (ix - r)]
            self._mask[win.slices(box)] |= disc
            drawn = win.union(drawn, box)
        self._pending = win.union(self._pending, win.union(self._drawn, drawn))
        self._drawn = drawn

    def update_bounds(self, pose: Pose2D, window: Window | None) -> Window | None:
        pending, self._pending = self._pending, None
        return win.union(window, pending)

    def update_costs(self, master: npt.NDArray[np.uint8], window: Window) -> None:
        region = win.slices(window)
        out = master[region]
        out[self._mask[region] & (out < self._cost)] = self._cost
