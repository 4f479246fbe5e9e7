"""Why a plan could not be made (after Nav2's ``planner_exceptions.hpp``)."""

from __future__ import annotations

from polynav.errors import PolynavError
from polynav.geometry import Pose2D
from polynav.maps import costs
from polynav.planning.path import Path


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


class NoBodyRoute(NoPath):
    """A polygon body fits no route, though a disk of its width would (the grid ``route``).

    ``blocked_at`` is the first pose along that route where the body touches something: a
    caller that knows which obstacles are the map's and which the lidar's marks (a person's
    trail) may follow ``route`` and let the controller deal with a block that will pass.
    """

    def __init__(self, message: str, *, route: Path, blocked_at: Pose2D) -> None:
        super().__init__(message)
        self.route = route
        self.blocked_at = blocked_at


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
