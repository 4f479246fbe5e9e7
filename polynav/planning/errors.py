"""Why a plan could not be made (after Nav2's ``planner_exceptions.hpp``)."""

from __future__ import annotations

from polynav.errors import PolynavError


class PlanningError(PolynavError):
    """Base of every planning failure."""


class OutsideMap(PlanningError):
    """The start or the goal lies outside the costmap."""


class StartOccupied(PlanningError):
    """The start cell is lethal (or inscribed): the robot sits in an obstacle."""


class GoalOccupied(PlanningError):
    """The goal cell is lethal (or inscribed) and no tolerance allows a nearby goal."""


class NoPath(PlanningError):
    """Start and goal are valid but not connected through traversable cells."""


class PlanningCancelled(PlanningError):
    """The caller gave up on the search."""
