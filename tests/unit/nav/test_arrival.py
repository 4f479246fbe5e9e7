"""Which arrivals stand, by the localization's uncertainty and the goal's demand."""

from __future__ import annotations

import pytest

from polynav.geometry import Pose2D
from polynav.localization.interface import (
    LocalizationEstimate,
    LocalizationState,
    PoseUncertainty,
)
from polynav.nav.arrival import Verdict, judge
from polynav.nav.attempt import DOCK_POSITION_UNCERTAINTY, GoalOptions

TRACKING = LocalizationState.TRACKING


def _estimate(position: float | None, state: LocalizationState = TRACKING
              ) -> LocalizationEstimate:
    uncertainty = None if position is None else PoseUncertainty(position, 0.01)
    return LocalizationEstimate(0.0, Pose2D(), 1.0, state, uncertainty)


def test_a_goal_that_demands_nothing_stands_on_dead_reckoning() -> None:
    assert judge(GoalOptions(), _estimate(0.5)) == Verdict(True)
    assert judge(GoalOptions(), None) == Verdict(True)


def test_a_precise_goal_stands_within_its_limit_and_fails_beyond_it() -> None:
    precise = GoalOptions(max_position_uncertainty=0.05)
    assert judge(precise, _estimate(0.05)).ok
    verdict = judge(precise, _estimate(0.24))
    assert not verdict.ok
    assert verdict.message == "position known to 0.240 m at the goal, 0.050 m required"


@pytest.mark.parametrize("state", [LocalizationState.LOST, LocalizationState.UNINITIALIZED])
def test_a_precise_goal_fails_when_localization_is_not_tracking(state) -> None:
    verdict = judge(GoalOptions(max_position_uncertainty=0.05), _estimate(0.01, state))
    assert verdict == Verdict(False, f"localization is {state.value} at the goal")


def test_a_precise_goal_fails_when_the_localizer_gives_no_uncertainty() -> None:
    assert not judge(GoalOptions(max_position_uncertainty=0.05), _estimate(None)).ok


def test_a_docking_goal_demands_the_dock_limit_unless_told_otherwise() -> None:
    assert GoalOptions(dock=True).required_position_uncertainty == DOCK_POSITION_UNCERTAINTY
    assert not judge(GoalOptions(dock=True), _estimate(0.08)).ok
    assert judge(GoalOptions(dock=True, max_position_uncertainty=0.1), _estimate(0.08)).ok


def test_a_non_positive_limit_is_refused() -> None:
    with pytest.raises(ValueError, match="max_position_uncertainty"):
        GoalOptions(max_position_uncertainty=0.0)
