"""The static layer: the saved map, turned into costs once and copied into the master.

Occupancy at or above ``lethal_threshold`` is LETHAL, everything else known is FREE (Nav2's
``trinary_costmap``). Unknown cells are UNKNOWN when the costmap tracks unknown space, and FREE
otherwise, so a robot can plan through unmapped corners when the user allows it.

The static layer is the base: it *overwrites* the master inside the window, as Nav2's
``StaticLayer`` does with ``updateWithOverwrite``.
"""

from __future__ import annotations

import logging

import numpy as np
import numpy.typing as npt

from polynav.geometry import Pose2D
from polynav.maps import costs
from polynav.maps.interface import Window
from polynav.maps.layers import window as win
from polynav.maps.map import Map

log = logging.getLogger(__name__)


def static_costs(grid: Map, *, lethal_threshold: int, track_unknown: bool) -> npt.NDArray[np.uint8]:
    """Costs of an occupancy map: LETHAL, FREE, and UNKNOWN (or FREE) for unknown cells."""
    data = grid.data
    out = np.full(data.shape, costs.FREE, dtype=np.uint8)
    if track_unknown:
        out[data < 0] = costs.UNKNOWN
    out[data >= lethal_threshold] = costs.LETHAL
    return out


class StaticLayer:
    """Costs from the occupancy map; changes only when the map is replaced."""

    def __init__(self, grid: Map, *, lethal_threshold: int, track_unknown: bool) -> None:
        self._lethal_threshold = lethal_threshold
        self._track_unknown = track_unknown
        self._info = grid.info
        self._costs = static_costs(
            grid, lethal_threshold=lethal_threshold, track_unknown=track_unknown
        )
        self._pending: Window | None = win.full(grid.info.width, grid.info.height)

    @property
    def costs(self) -> npt.NDArray[np.uint8]:
        """This layer's own costs ``[iy, ix]`` (read them, do not write)."""
        return self._costs

    def set_map(self, grid: Map) -> None:
        """Replace the map with one of the same geometry; only the cells that differ get redrawn.

        Raises:
            ValueError: ``grid`` has another size, resolution or origin (build a new layer).
        """
        if grid.info != self._info:
            raise ValueError("StaticLayer.set_map needs a map of the same geometry")
        new = static_costs(
            grid, lethal_threshold=self._lethal_threshold, track_unknown=self._track_unknown
        )
        changed = win.of_mask(new != self._costs)
        self._costs = new
        self._pending = win.union(self._pending, changed)
        log.debug("static layer: map replaced, changed window %s", changed)

    def update_bounds(self, pose: Pose2D, window: Window | None) -> Window | None:
        pending, self._pending = self._pending, None
        return win.union(window, pending)

    def update_costs(self, master: npt.NDArray[np.uint8], window: Window) -> None:
        region = win.slices(window)
        master[region] = self._costs[region]
