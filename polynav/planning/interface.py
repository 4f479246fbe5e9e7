"""What a global planner is: a function from a cost grid, a start and a goal to a path."""

from __future__ import annotations

from typing import Protocol

from polynav.geometry import Pose2D
from polynav.maps.interface import CostGrid
from polynav.planning.path import Path


class GlobalPlanner(Protocol):
    def plan(
        self,
        costmap: CostGrid,
        start: Pose2D,
        goal: Pose2D,
        *,
        goal_tolerance: float | None = None,
    ) -> Path:
        """A path from ``start`` to ``goal``; raises a :class:`PlanningError` subclass if none.

        ``goal_tolerance`` [m]: when the goal is occupied or unreachable, a path to the nearest
        reachable point within this distance of it is accepted (``None``: the planner's own).
        """
        ...
