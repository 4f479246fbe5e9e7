"""Why a plan could not be made (after Nav2's ``planner_exceptions.hpp``)."""

from __future__ import annotations

from polynav.errors import PolynavError
from polynav.maps import costs


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


def failure_cause(exc: PlanningError, start_cost: int) -> str:
    """The cause a failed plan is reported with (``PlanFailed.cause``), given the cost under the
    robot: a start in unknown space or on an obstacle explains any failure, whatever the
    planner raised."""
    if isinstance(exc, OutsideMap):
        return "outside_map"
    if start_cost == costs.UNKNOWN:
        return "start_unknown"
    if isinstance(exc, StartOccupied) or start_cost == costs.LETHAL:
        return "start_occupied"
    if isinstance(exc, GoalOccupied):
        return "goal_occupied"
    return "no_path"
