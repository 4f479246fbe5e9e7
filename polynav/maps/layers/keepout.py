"""The keepout layer: virtual walls and forbidden zones, LETHAL on top of the map.

It comes after the static layer and before inflation, so the robot keeps its radius away from a
keepout as from a wall. A keepout is a hard rule, so its cells are LETHAL even where the map is
unknown. Changing the keepouts redraws only the cells that changed.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

from polynav.geometry import Pose2D
from polynav.maps import costs
from polynav.maps.interface import Window
from polynav.maps.keepout import Keepout, rasterize
from polynav.maps.layers import window as win
from polynav.maps.map import MapInfo

log = logging.getLogger(__name__)


class KeepoutLayer:
    """LETHAL cells drawn from a set of :data:`~polynav.maps.keepout.Keepout` shapes."""

    def __init__(self, info: MapInfo, keepouts: Sequence[Keepout] = ()) -> None:
        self._info = info
        self._keepouts: tuple[Keepout, ...] = ()
        self._mask = np.zeros((info.height, info.width), dtype=np.bool_)
        self._pending: Window | None = None
        self.set_keepouts(keepouts)

    @property
    def keepouts(self) -> tuple[Keepout, ...]:
        return self._keepouts

    @property
    def mask(self) -> npt.NDArray[np.bool_]:
        """Cells ``[iy, ix]`` covered by a keepout (read them, do not write)."""
        return self._mask

    def set_keepouts(self, keepouts: Sequence[Keepout]) -> None:
        """Replace all keepouts; the cells that changed are redrawn at the next update."""
        new = rasterize(keepouts, self._info)
        changed = win.of_mask(new != self._mask)
        self._keepouts = tuple(keepouts)
        self._mask = new
        self._pending = win.union(self._pending, changed)
        log.debug("keepout layer: %d keepouts, changed window %s", len(keepouts), changed)

    def update_bounds(self, pose: Pose2D, window: Window | None) -> Window | None:
        pending, self._pending = self._pending, None
        return win.union(window, pending)

    def update_costs(self, master: npt.NDArray[np.uint8], window: Window) -> None:
        region = win.slices(window)
        master[region][self._mask[region]] = costs.LETHAL
