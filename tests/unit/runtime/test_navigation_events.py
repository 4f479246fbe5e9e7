"""Navigator events as runtime events: what a success says about the pose it ended on."""

from __future__ import annotations

from dataclasses import replace

from polynav.geometry import Pose2D
from polynav.localization.interface import PoseUncertainty
from polynav.nav import events as nav_events
from polynav.nav.attempt import NavigationAttempt, NavigationState
from polynav.runtime import events
from polynav.runtime.navigation_events import translate

ATTEMPT = NavigationAttempt(attempt_id=1, goal=Pose2D(3.0, 4.0, 0.0),
                            state=NavigationState.SUCCEEDED, started_at=0.0, ended_at=9.0,
                            distance_travelled=5.0)


def test_a_success_carries_the_uncertainty_the_robot_arrived_with() -> None:
    attempt = replace(ATTEMPT, arrival_uncertainty=PoseUncertainty(0.24, 0.006))
    (out,) = translate(nav_events.NavigationSucceeded(9.0, attempt), 7, None)
    assert out == events.NavigationSucceeded(9.0, 7, 5.0, position_uncertainty=0.24,
                                             heading_uncertainty=0.006)
    assert out.to_dict()["position_uncertainty"] == 0.24


def test_a_success_without_an_uncertainty_says_none() -> None:
    (out,) = translate(nav_events.NavigationSucceeded(9.0, ATTEMPT), 7, None)
    assert isinstance(out, events.NavigationSucceeded)
    assert out.position_uncertainty is None and out.heading_uncertainty is None
