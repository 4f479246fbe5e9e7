"""In-map path lengths for the router, planned by the real planner and cached per map version.

Each map's costmap is built from its stored map and keepouts (static layers only: the router
weighs routes, the navigator plans the live path when it drives), and every length planned on
it is kept until the map's record or its keepouts change, when the costmap and its lengths are
dropped together. Lengths between connection points are thus planned once per map version;
only the legs from where the robot stands are planned per route.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Protocol

from polynav.geometry import Pose2D
from polynav.maps.costmap import Costmap, CostmapConfig, CostSnapshot
from polynav.maps.keepout import Keepout
from polynav.maps.map import Map
from polynav.planning.errors import NoPath, PlanningError
from polynav.planning.grid_planner import GridPlanner, GridPlannerConfig

log = logging.getLogger(__name__)

_Key = tuple[float, float, float, float]


class MapSource(Protocol):
    """The part of the site store path costs read."""

    def map_record(self, name: str) -> object: ...

    def load_map(self, name: str) -> Map: ...

    def keepouts(self, map_name: str) -> Sequence[Keepout]: ...


@dataclass(slots=True)
class _MapCosts:
    version: object
    snapshot: CostSnapshot
    lengths: dict[_Key, float | None] = field(default_factory=dict)


class PlannedPathCosts:
    """:class:`~polynav.routing.router.PathCosts` on the stored maps (see the module docstring).

    Args:
        store: the site's maps and keepouts.
        costmap: how the costmaps are built (inflation as the robot's own).
        planner: the planner's settings (as the robot's own).
    """

    def __init__(self, store: MapSource, costmap: CostmapConfig,
                 planner: GridPlannerConfig) -> None:
        self._store = store
        self._costmap_config = costmap
        self._planner = GridPlanner(planner)
        self._maps: dict[str, _MapCosts] = {}
        self._lock = threading.Lock()
        self.plans = 0
        """How many plans were made (the rest were answered from the cache)."""

    def length(self, map_name: str, start: Pose2D, goal: Pose2D) -> float:
        """Length [m] of the planned path from ``start`` to ``goal`` on ``map_name``.

        Raises:
            NotFound: unknown map.
            PlanningError: no path.
        """
        costs = self._costs(map_name)
        key = (round(start.x, 2), round(start.y, 2), round(goal.x, 2), round(goal.y, 2))
        with self._lock:
            known = costs.lengths.get(key, -1.0)
        if known is None:
            raise NoPath(f"no path on {map_name} (cached)")
        if known >= 0.0:
            return known
        self.plans += 1
        try:
            length = self._planner.plan(costs.snapshot, start, goal).length
        except PlanningError:
            with self._lock:
                costs.lengths[key] = None
            raise
        with self._lock:
            costs.lengths[key] = length
        return length

    def _costs(self, map_name: str) -> _MapCosts:
        record = self._store.map_record(map_name)
        keepouts = tuple(self._store.keepouts(map_name))
        version = (record, keepouts)
        with self._lock:
            cached = self._maps.get(map_name)
            if cached is not None and cached.version == version:
                return cached
        costmap = Costmap.from_map(self._store.load_map(map_name), self._costmap_config)
        if keepouts:
            costmap.set_keepouts(keepouts)
        entry = _MapCosts(version, costmap.snapshot())
        with self._lock:
            self._maps[map_name] = entry
        log.debug("path costs of map %s (re)built", map_name)
        return entry
