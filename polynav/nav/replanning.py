"""Periodic re-planning: the stretch near the robot every few seconds, the whole way now and then.

The navigator re-plans every ``replan_period`` so that what the lidar has seen since the last
plan (a person, a trolley, a door left open) is routed round before the controller must stop
for it. Planning the whole way each time costs what the floor costs: on a 200 m floor at 5 cm
(16 million cells) one A* takes a fifth of a second, most of a robot's CPU. Yet between two
re-plans only what the lidar sees changes, and it sees a few metres. So a periodic re-plan plans
from the robot to the point of the current route ``reach`` metres ahead and splices the rest of
the route on: the same answer where nothing changed farther on, for the cost of a few metres.
Every ``full_period`` the whole way is planned again, which finds an altogether different way
when one has opened (the door that was blocked when the route was chosen). When the stretch
cannot be planned (its end point is occupied, or no way reaches it) the whole way is planned at
once.

People are the exception to "now and then": when they close the route (a walker in a door) and
the robot takes a way round, the way they closed is usually the shorter and opens again within
seconds, as they walk on. Waiting up to ``full_period`` to notice sends the robot the long way
round, often into a narrower passage with people of its own. So after such a detour (:meth:`watch`)
every re-plan plans the whole way for ``watch_for`` seconds.

Whichever was planned, the new route replaces the current one only as :mod:`route_choice`
decides (blocked, or clearly shorter).
"""

from __future__ import annotations

import logging
import math

import numpy as np

from polynav.control.tracked_path import TrackedPath
from polynav.geometry import Pose2D
from polynav.maps.interface import CostGrid
from polynav.planning.errors import PlanningError
from polynav.planning.interface import GlobalPlanner
from polynav.planning.path import Path

log = logging.getLogger(__name__)


def spliced(stretch: Path, route: TrackedPath, rejoin: float) -> Path:
    """``stretch`` (ending on ``route`` at arc length ``rejoin`` [m]) and the route from there."""
    later = route.cumulative > rejoin + 1e-9
    points = np.vstack([stretch.points, route.points[later]])
    return Path(points, cost=stretch.cost + float(route.length - rejoin))


class PeriodicReplan:
    """Plans the periodic re-plans of one navigation (module docstring).

    Args:
        planner: the global planner.
        reach: how far ahead along the route [m] a near re-plan rejoins it; 0 always plans the
            whole way.
        full_period: the whole way is planned at least this often [s].
        watch_for: after a detour round people, the whole way is planned at every re-plan for
            this long [s].
    """

    def __init__(self, planner: GlobalPlanner, *, reach: float, full_period: float,
                 watch_for: float = 0.0) -> None:
        self._planner = planner
        self.reach = reach
        self.full_period = full_period
        self.watch_for = watch_for
        self._last_full = -math.inf
        self._watch_until = -math.inf

    def reset(self) -> None:
        """A new goal: no whole-way plan made yet and no watch for people running. A watch
        begun for the previous goal's detour says nothing about the new goal's route, and
        kept, it would have the new goal's first re-plans plan the whole way."""
        self._last_full = -math.inf
        self._watch_until = -math.inf

    def watch(self, now: float) -> None:
        """People closed the route and the robot took a way round them (module docstring)."""
        self._watch_until = now + self.watch_for

    def whole_way_planned(self, now: float) -> None:
        """A plan of the whole way was made (the first of a goal, or after a failure)."""
        self._last_full = now

    def plan(
        self,
        costmap: CostGrid,
        pose: Pose2D,
        target: Pose2D,
        route: TrackedPath | None,
        along: float,
        now: float,
        *,
        goal_tolerance: float | None,
    ) -> Path:
        """A new route from ``pose``: the stretch to ``reach`` ahead spliced onto ``route``, or
        the whole way to ``target``.

        Raises:
            PlanningError: the whole way could not be planned.
        """
        rejoin = along + self.reach
        if (
            route is not None
            and self.reach > 0.0
            and now - self._last_full < self.full_period
            and now >= self._watch_until
            and rejoin < route.length
        ):
            x, y = route.point_at(rejoin)
            try:
                stretch = self._planner.plan(costmap, pose, Pose2D(x, y, target.theta))
            except PlanningError as exc:
                log.debug("re-plan of the next %.1f m failed (%s): planning the whole way",
                          self.reach, exc)
            else:
                return spliced(stretch, route, rejoin)
        path = self._planner.plan(costmap, pose, target, goal_tolerance=goal_tolerance)
        self._last_full = now
        return path
