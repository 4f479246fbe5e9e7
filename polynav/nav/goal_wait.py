"""Waiting for the goal to clear: the navigator's *goal wait* phase.

A goal the planner still finds occupied after the lidar's marks were cleared was final: right
when the map or a keepout covers it (a goal in a wall stays in a wall), wrong when only what the
lidar sees now stands there: another robot waiting to leave the room it was sent to, a trolley
left for a minute. Someone who walks there is the people wait's (:mod:`~polynav.nav.people_wait`);
anything else that is not on the map gets :class:`GoalWait`: the robot stands where it is, plans
again every ``period``, goes on as soon as the goal is free, and fails ``goal occupied`` only
after ``patience``. In a building with several robots this is common: a robot waiting in line
for the corridor stands on the room point the next robot is sent to.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from typing import Protocol

from polynav.geometry import Pose2D
from polynav.maps import costs
from polynav.nav.people_wait import WaitStep
from polynav.planning.errors import PlanningError
from polynav.planning.path import Path

log = logging.getLogger(__name__)


class MapCosts(Protocol):
    """The costmap's answer without the lidar (:meth:`polynav.maps.costmap.Costmap.map_cost_at`)."""

    def map_cost_at(self, x: float, y: float) -> int: ...


class GoalWait:
    """The current wait for the goal to clear (one goal at a time).

    Args:
        costmap: tells the map's cells from the lidar's.
        patience: how long [s] the robot waits for the goal before the goal fails; 0 fails at
            once, as a goal in a wall does.
        period: how often [s] it plans again meanwhile.
    """

    def __init__(self, costmap: MapCosts, *, patience: float, period: float) -> None:
        self._costmap = costmap
        self.patience = patience
        self.period = period
        self._since: float | None = None
        self._last_try = 0.0

    def reset(self, patience: float | None = None) -> None:
        """Forget the wait (a new goal, with its own ``patience`` if given)."""
        self._since = None
        if patience is not None:
            self.patience = patience

    def may_clear(self, goal: Pose2D) -> bool:
        """Whether the goal is worth waiting for: free on the map and the keepouts, so only
        something standing there now holds it."""
        return self.patience > 0.0 and self._costmap.map_cost_at(goal.x, goal.y) < costs.INSCRIBED

    def begin(self, now: float) -> bool:
        """Start waiting (``True``: a new wait, to be told once), or go on with the wait."""
        self._last_try = now
        if self._since is not None:
            return False
        self._since = now
        log.info("the goal is occupied by something not on the map: waiting up to %g s for it",
                 self.patience)
        return True

    def tick(self, pose: Pose2D, now: float, plan: Callable[[Pose2D], Path]) -> WaitStep:
        """One control period of the wait: stand, and every ``period`` try to plan."""
        assert self._since is not None, "tick() outside a wait"
        if now - self._last_try < self.period:
            return WaitStep()
        self._last_try = now
        try:
            path = plan(pose)
        except PlanningError as exc:
            if now - self._since >= self.patience:
                return WaitStep(expired=True)
            log.debug("goal still occupied: %s", exc)
            return WaitStep()
        log.info("the goal cleared after %.1f s: going on", now - self._since)
        self._since = None
        return WaitStep(path=path)
