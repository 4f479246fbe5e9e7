"""Interfaces of the maps package: what a costmap layer is and what a planner reads.

Only stdlib, numpy and polynav value types are imported here (the ``nav2_core`` rule).
"""

from __future__ import annotations

from typing import Protocol

import numpy as np
import numpy.typing as npt

from polynav.geometry import Pose2D
from polynav.maps.map import MapInfo

Window = tuple[int, int, int, int]
"""A cell window ``(ix0, iy0, ix1, iy1)``, half-open: ``ix0 <= ix < ix1``, ``iy0 <= iy < iy1``."""


class CostGrid(Protocol):
    """Anything a planner or controller can read costs from: a costmap or a frozen snapshot."""

    @property
    def info(self) -> MapInfo: ...

    @property
    def costs(self) -> npt.NDArray[np.uint8]: ...


class CostmapLayer(Protocol):
    """One layer of the costmap (Lu et al., IROS 2014; Nav2 ``layer.hpp``).

    The costmap first asks each layer which window it needs to redraw, then asks it to write its
    costs into the master grid inside the union window, never outside it.
    """

    def update_bounds(self, pose: Pose2D, window: Window | None) -> Window | None:
        """Grow ``window`` (or start one from ``None``) by the cells this layer changed."""
        ...

    def update_costs(self, master: npt.NDArray[np.uint8], window: Window) -> None:
        """Write this layer's costs into ``master[iy0:iy1, ix0:ix1]``."""
        ...
