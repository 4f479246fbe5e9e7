"""Frontier exploration: the robot maps a floor on its own, then comes back to where it started.

Runs inside a mapping session (Yamauchi, "A frontier-based approach for autonomous exploration",
1997). Every ``replan_period`` seconds of the robot's clock, or when it reached or failed its
target, the live map is searched for *frontiers*: free cells next to unknown ones, grouped into
connected clusters; clusters smaller than ``min_frontier`` metres are noise. The nearest cluster
the planner can reach on the live costmap (its cell nearest the robot, as close as the costmap
allows) becomes the target, and a :class:`~polynav.nav.navigator.Navigator` drives there with
the SLAM pose as its localization, avoiding what the lidar sees. When no reachable frontier is
left the robot drives back to its start, and the exploration is done.
"""

from __future__ import annotations

import enum
import logging
import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from scipy import ndimage

from polynav.control.progress_checker import ProgressChecker, ProgressCheckerConfig
from polynav.control.pure_pursuit import PurePursuitConfig, RegulatedPurePursuit
from polynav.errors import ConfigError
from polynav.geometry import Pose2D, Twist
from polynav.localization.interface import LocalizationEstimate, LocalizationState
from polynav.maps import costs
from polynav.maps.costmap import Costmap, CostmapConfig
from polynav.maps.map import FREE, Map
from polynav.nav.attempt import GoalOptions, NavigationState
from polynav.nav.navigator import Navigator
from polynav.nav.navigator_config import NavigatorConfig
from polynav.planning.errors import PlanningError
from polynav.planning.grid_planner import GridPlanner, GridPlannerConfig
from polynav.robot.interface import LaserScan

log = logging.getLogger(__name__)

_HOMEWARD_TRIES = 5


@dataclass(frozen=True, slots=True)
class ExplorationConfig:
    """How the robot explores [m, s].

    Attributes:
        replan_period: how often the frontiers are looked at again while driving.
        min_frontier: frontier clusters shorter than this are noise (a gap between two scans).
        goal_tolerance: how near a frontier counts as reached.
        costmap: the live costmap's settings (the robot's radius and inflation).
        controller: the path follower's settings.
        time_limit: the exploration ends (and the robot heads home) after this long.
    """

    replan_period: float = 5.0
    min_frontier: float = 0.6
    goal_tolerance: float = 0.5
    costmap: CostmapConfig = field(default_factory=lambda: CostmapConfig(track_unknown=True))
    controller: PurePursuitConfig = field(default_factory=PurePursuitConfig)
    time_limit: float = 1800.0

    def __post_init__(self) -> None:
        for key in ("replan_period", "min_frontier", "goal_tolerance", "time_limit"):
            value = getattr(self, key)
            if not (math.isfinite(value) and value > 0.0):
                raise ConfigError(f"mapping.exploration.{key}", f"must be > 0, got {value}")


class Stage(enum.Enum):
    EXPLORING = "exploring"
    RETURNING = "returning"
    DONE = "done"


def frontiers(grid: Map, passable: np.ndarray, min_cells: int) -> list[np.ndarray]:
    """Clusters of frontier cells (``(k, 2)`` arrays of ``[ix, iy]``), largest first.

    A frontier cell is free, where the robot fits (``passable``), with an unknown neighbour.
    """
    data = grid.data
    unknown = data < 0
    near_unknown = ndimage.binary_dilation(unknown, structure=np.ones((3, 3), dtype=bool))
    cells = (data == FREE) & near_unknown & passable
    labels, count = ndimage.label(cells, structure=np.ones((3, 3), dtype=bool))
    # Every cluster's cells in one pass (a stable sort by label keeps each cluster's cells in
    # row-major order, as ``np.nonzero(labels == k)`` would give them, at one pass per label).
    flat = np.flatnonzero(labels)
    ids = labels.ravel()[flat]
    order = np.argsort(ids, kind="stable")
    iy, ix = np.divmod(flat[order], data.shape[1])
    bounds = np.searchsorted(ids[order], np.arange(1, count + 2))
    out = [np.column_stack((ix[a:b], iy[a:b]))
           for a, b in zip(bounds[:-1].tolist(), bounds[1:].tolist(), strict=True)
           if b - a >= min_cells]
    out.sort(key=lambda c: -c.shape[0])
    return out


class Exploration:
    """Drives the robot to frontiers of the live map, then home."""

    def __init__(self, start: Pose2D, config: ExplorationConfig | None = None) -> None:
        self.config = config or ExplorationConfig()
        self.start = start
        self.stage = Stage.EXPLORING
        self.targets = 0
        self.reached = 0
        """Frontier targets driven to and reached."""
        self.frontiers_left: int | None = None
        """Frontier clusters the last search found worth a visit (``None`` before the first;
        0 once none is left or the time is up)."""
        self._navigator: Navigator | None = None
        self._costmap: Costmap | None = None
        self._planner = GridPlanner(GridPlannerConfig())
        self._next_plan = -math.inf
        self._began: float | None = None
        # Frontiers not to choose again: those that could not be reached, and those reached
        # that are still frontiers (the edge of a shadow no pose near it sees into).
        self._failed: list[tuple[float, float]] = []
        self._homeward = 0  # tries to drive back to the start

    @property
    def done(self) -> bool:
        return self.stage is Stage.DONE

    def tick(self, now: float, live_map: Callable[[], Map], pose: Pose2D, velocity: Twist,
             scan: LaserScan | None, estop: bool) -> Twist:
        """One control period: the velocity to command (``live_map`` is rendered only when a
        new target is chosen)."""
        if self.stage is Stage.DONE:
            return Twist()
        if self._began is None:
            self._began = now
        navigator = self._navigator
        finished = navigator is None or navigator.state is not NavigationState.RUNNING
        if (finished and navigator is not None and self.stage is Stage.EXPLORING
                and navigator.state in (NavigationState.FAILED, NavigationState.SUCCEEDED)):
            attempt = navigator.attempt
            if attempt is not None:
                self._failed.append((attempt.goal.x, attempt.goal.y))
            if navigator.state is NavigationState.SUCCEEDED:
                self.reached += 1
        if finished or now >= self._next_plan:
            if self.stage is Stage.RETURNING and finished and navigator is not None:
                home = navigator.state is NavigationState.SUCCEEDED
                if home or self._homeward >= _HOMEWARD_TRIES:
                    log.info("exploration done after %d targets, %s", self.targets,
                             "back at the start" if home else "could not get back")
                    self.stage = Stage.DONE
                    return Twist()
            self._next_plan = now + self.config.replan_period
            self._choose(now, live_map(), pose, keep=not finished)
        navigator = self._navigator
        if navigator is None or self._costmap is None:
            return Twist()
        if scan is not None:
            self._costmap.update_scan(pose, scan)
        estimate = LocalizationEstimate(now, pose, 1.0, LocalizationState.TRACKING)
        return navigator.tick(now, estimate, velocity, estop)

    def _choose(self, now: float, grid: Map, pose: Pose2D, *, keep: bool) -> None:
        cfg = self.config
        costmap = Costmap(grid, cfg.costmap)
        passable = costmap.costs < costs.INSCRIBED
        target: Pose2D | None = None
        timed_out = self._began is not None and now - self._began >= cfg.time_limit
        if self.stage is Stage.EXPLORING and not timed_out:
            target = self._nearest_frontier(costmap, grid, passable, pose)
            if target is None and keep and self._navigator is not None:
                return  # the current target is still worth reaching
        if target is None and self.stage is Stage.EXPLORING:
            self.frontiers_left = 0  # none reachable, or no time left to visit them
            log.info("no frontier left after %d targets: going back to the start", self.targets)
            self.stage = Stage.RETURNING
            target = self.start
            self._homeward = 1
        elif target is None:
            if keep and self._navigator is not None:
                return  # still on its way home: a periodic look is no new try
            target = self.start
            self._homeward += 1  # the last way home failed (success ended the exploration)
            log.info("the way back failed; trying again (%d of %d)", self._homeward,
                     _HOMEWARD_TRIES)
        self._costmap = costmap
        # A frontier that turns out occupied is given up for the next one, not waited for.
        self._navigator = Navigator(
            costmap, self._planner, RegulatedPurePursuit(cfg.controller),
            ProgressChecker(ProgressCheckerConfig()),
            config=NavigatorConfig(max_retries=2, goal_wait=0.0),
            robot_radius=cfg.costmap.robot_radius,
        )
        tolerance = cfg.goal_tolerance if self.stage is Stage.EXPLORING else None
        self._navigator.start(target, now, GoalOptions(pass_tolerance=tolerance,
                                                       near_tolerance=cfg.goal_tolerance))
        if self.stage is Stage.EXPLORING:
            self.targets += 1

    def _nearest_frontier(self, costmap: Costmap, grid: Map, passable: np.ndarray,
                          pose: Pose2D) -> Pose2D | None:
        info = grid.info
        min_cells = max(1, int(self.config.min_frontier / info.resolution))
        candidates = []
        for cluster in frontiers(grid, passable, min_cells):
            world = info.cells_to_world(cluster)
            d = np.hypot(world[:, 0] - pose.x, world[:, 1] - pose.y)
            k = int(np.argmin(d))
            x, y = float(world[k, 0]), float(world[k, 1])
            if any(math.hypot(x - fx, y - fy) < 1.0 for fx, fy in self._failed):
                continue
            if d[k] <= self.config.goal_tolerance:
                # Already there and still a frontier: nothing more to see from here.
                self._failed.append((x, y))
                continue
            candidates.append((float(d[k]), Pose2D(x, y, math.atan2(y - pose.y, x - pose.x))))
        left = len(candidates)
        for _, goal in sorted(candidates, key=lambda c: c[0])[:5]:
            try:
                self._planner.plan(costmap, pose, goal)
            except PlanningError:
                self._failed.append((goal.x, goal.y))
                left -= 1
                continue
            self.frontiers_left = left
            return goal
        self.frontiers_left = 0
        return None
