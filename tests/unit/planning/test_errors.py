"""The cause a failed plan is reported with: where the robot stands explains any failure."""

from __future__ import annotations

import pytest

from polynav.maps import costs
from polynav.planning.errors import (
    GoalOccupied,
    NoPath,
    OutsideMap,
    PlanningError,
    StartOccupied,
    failure_cause,
)


@pytest.mark.parametrize(("exc", "start_cost", "cause"), [
    (OutsideMap("far"), costs.UNKNOWN, "outside_map"),
    (NoPath("x"), costs.UNKNOWN, "start_unknown"),
    (GoalOccupied("x"), costs.LETHAL, "start_occupied"),
    (StartOccupied("x"), costs.INSCRIBED, "start_occupied"),
    (GoalOccupied("x"), costs.FREE, "goal_occupied"),
    (NoPath("x"), costs.FREE, "no_path"),
    (NoPath("x"), costs.INSCRIBED, "no_path"),
])
def test_failure_cause(exc: PlanningError, start_cost: int, cause: str) -> None:
    assert failure_cause(exc, start_cost) == cause
