"""How much of the floor is mapped, for the status, counted as the scans come in.

The live map's known cells are the honest measure, but rendering it inserts every scan again:
0.4-0.5 s on the loop thread for the explored demo floor (2,900 nodes), too much once a second.
:class:`MappedArea` keeps a grid of its own instead, with the SLAM's cell size and thresholds:
each scan that becomes a SLAM node is inserted once, at the pose the SLAM gave it then (one
insertion: what the SLAM does for its submaps anyway), and the known cells are counted at most
once per :data:`AREA_PERIOD` of the runtime's clock. A later loop closure moves the live map's
cells, not this grid's, so the two differ by the drift corrected: the area is a progress
figure, the map is the map. An updated map starts with the saved map's known cells.
"""

from __future__ import annotations

import math

import numpy as np

from polynav.geometry import Pose2D
from polynav.localization.scan_matcher import scan_points
from polynav.mapping.config import SlamConfig
from polynav.mapping.occupancy import LogOddsGrid, log_odds
from polynav.maps.map import Map
from polynav.robot.interface import LaserScan

AREA_PERIOD = 1.0
"""How often the known cells are counted again [s of the runtime's clock], when scans came in."""


class MappedArea:
    """Known (free or occupied) cells x the cell's area [m²] of the map being built.

    Args:
        config: the SLAM's parameters (cell size, beam model, thresholds, range).
        prior: the saved map being updated, if any (its known cells count from the start).
    """

    def __init__(self, config: SlamConfig, prior: Map | None = None) -> None:
        self._config = config
        hit, miss = log_odds(config.hit_probability), log_odds(config.miss_probability)
        if prior is None:
            self._grid = LogOddsGrid(config.resolution, hit=hit, miss=miss)
        else:
            self._grid = LogOddsGrid.seeded(prior, hit=hit, miss=miss, level=1.0)
        self._free = log_odds(config.free_probability)
        self._occupied = log_odds(config.occupied_probability)
        self._area = self._count() if prior is not None else 0.0
        self._changed = False
        self._due = -math.inf

    def insert(self, pose: Pose2D, scan: LaserScan) -> None:
        """Insert a scan the SLAM made a node of, at its pose on the map being built."""
        c = self._config
        mount = scan.sensor_pose or Pose2D()
        points = scan_points(scan.ranges, np.asarray(scan.angles, dtype=np.float64),
                             range_min=c.range_min, range_max=c.range_max, sensor_pose=mount)
        self._grid.insert(pose, points, np.array([mount.x, mount.y]))
        self._changed = True

    def area(self, now: float) -> float:
        """The mapped area [m²], counted again if due (``now``: the runtime's clock)."""
        if self._changed and now >= self._due:
            self._due = now + AREA_PERIOD
            self._changed = False
            self._area = self._count()
        return self._area

    def _count(self) -> float:
        values = self._grid.values
        known = np.count_nonzero((values <= self._free) | (values >= self._occupied))
        return float(known) * self._config.resolution ** 2
