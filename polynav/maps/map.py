"""The occupancy map: a grid of occupancy values with its place in the world.

Values follow ROS ``nav_msgs/OccupancyGrid``: 0 free, 100 occupied, 1..99 partly occupied (scale
mode), -1 unknown. Arrays are indexed ``grid[iy, ix]`` with row ``iy = 0`` at the *bottom* of the
map image (the ROS convention), so ``iy`` grows with world ``y``. All world/cell conversion goes
through :class:`MapInfo` (Nav2 ``worldToMap``/``mapToWorld``), nowhere else.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from polynav.geometry import Pose2D

OCCUPIED = 100
FREE = 0
UNKNOWN = -1


@dataclass(frozen=True, slots=True)
class MapInfo:
    """Where a grid sits in the world: cell size [m], size in cells, and the origin pose.

    ``origin`` is the world pose of the lower-left corner of cell (0, 0) (ROS map_server).
    """

    resolution: float
    width: int
    height: int
    origin: Pose2D = Pose2D()

    def world_to_cell(self, x: float, y: float) -> tuple[int, int]:
        """Cell (ix, iy) holding world point (x, y); may lie outside the grid (see ``contains``)."""
        lx, ly = self._to_local(x, y)
        return (math.floor(lx / self.resolution), math.floor(ly / self.resolution))

    def _to_local(self, x: float, y: float) -> tuple[float, float]:
        dx, dy = x - self.origin.x, y - self.origin.y
        c, s = math.cos(self.origin.theta), math.sin(self.origin.theta)
        return (c * dx + s * dy, -s * dx + c * dy)

    def cell_to_world(self, ix: float, iy: float) -> tuple[float, float]:
        """World point at the centre of cell (ix, iy)."""
        lx = (ix + 0.5) * self.resolution
        ly = (iy + 0.5) * self.resolution
        c, s = math.cos(self.origin.theta), math.sin(self.origin.theta)
        return (self.origin.x + c * lx - s * ly, self.origin.y + s * lx + c * ly)

    def contains(self, ix: int, iy: int) -> bool:
        return 0 <= ix < self.width and 0 <= iy < self.height

    def world_to_cells(self, xy: npt.NDArray[np.float64]) -> npt.NDArray[np.int64]:
        """Vectorised :meth:`world_to_cell` for an (N, 2) array of points.

        Returns:
            (N, 2) array of [ix, iy].
        """
        pts = np.asarray(xy, dtype=np.float64).reshape(-1, 2)
        c, s = math.cos(self.origin.theta), math.sin(self.origin.theta)
        dx = pts[:, 0] - self.origin.x
        dy = pts[:, 1] - self.origin.y
        lx = c * dx + s * dy
        ly = -s * dx + c * dy
        out = np.empty((pts.shape[0], 2), dtype=np.int64)
        out[:, 0] = np.floor(lx / self.resolution)
        out[:, 1] = np.floor(ly / self.resolution)
        return out

    def cells_to_world(self, cells: npt.NDArray[np.integer]) -> npt.NDArray[np.float64]:
        """Vectorised :meth:`cell_to_world` for an (N, 2) array of [ix, iy]; returns (N, 2)."""
        cs = np.asarray(cells, dtype=np.float64).reshape(-1, 2)
        lx = (cs[:, 0] + 0.5) * self.resolution
        ly = (cs[:, 1] + 0.5) * self.resolution
        c, s = math.cos(self.origin.theta), math.sin(self.origin.theta)
        out = np.empty_like(cs)
        out[:, 0] = self.origin.x + c * lx - s * ly
        out[:, 1] = self.origin.y + s * lx + c * ly
        return out

    def cells_within(self, x: float, y: float, radius: float) -> npt.NDArray[np.int64]:
        """The cells of the grid whose centres lie within ``radius`` [m] of world (x, y), as an
        (N, 2) array of [ix, iy]."""
        cx, cy = self.world_to_cell(x, y)
        reach = int(math.ceil(radius / self.resolution))
        span = np.arange(-reach, reach + 1)
        ix, iy = np.meshgrid(cx + span, cy + span)
        cells = np.column_stack((ix.ravel(), iy.ravel())).astype(np.int64)
        inside = (cells[:, 0] >= 0) & (cells[:, 1] >= 0) & (cells[:, 0] < self.width) & (
            cells[:, 1] < self.height)
        cells = cells[inside]
        centres = self.cells_to_world(cells)
        near = np.hypot(centres[:, 0] - x, centres[:, 1] - y) <= radius
        return np.asarray(cells[near])

    @property
    def size_m(self) -> tuple[float, float]:
        """Width and height [m]."""
        return (self.width * self.resolution, self.height * self.resolution)


@dataclass(frozen=True, slots=True, eq=False)
class Map:
    """An occupancy grid (int8, ``data[iy, ix]``) and its :class:`MapInfo`."""

    info: MapInfo
    data: npt.NDArray[np.int8]

    def __post_init__(self) -> None:
        if self.data.shape != (self.info.height, self.info.width):
            raise ValueError(
                f"map data shape {self.data.shape} does not match "
                f"{self.info.height}x{self.info.width}"
            )

    @classmethod
    def from_occupied(
        cls,
        occupied: npt.NDArray[np.bool_],
        *,
        resolution: float,
        origin: Pose2D | None = None,
    ) -> Map:
        """A free/occupied map from a boolean grid (``True`` = occupied), ``[iy, ix]``."""
        origin = origin or Pose2D()
        h, w = occupied.shape
        data = np.where(occupied, OCCUPIED, FREE).astype(np.int8)
        return cls(MapInfo(resolution=resolution, width=w, height=h, origin=origin), data)

    def occupied(self, threshold: int = 65) -> npt.NDArray[np.bool_]:
        """Boolean grid of cells at or above ``threshold`` occupancy (unknown is not occupied)."""
        return self.data >= threshold

    def is_free_at(self, x: float, y: float) -> bool:
        """True if world point (x, y) is inside the map on a known free cell."""
        ix, iy = self.info.world_to_cell(x, y)
        return self.info.contains(ix, iy) and 0 <= int(self.data[iy, ix]) < 50
