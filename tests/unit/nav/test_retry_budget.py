"""The retry budget forgets failures only where the robot got closer to its goal."""

from __future__ import annotations

from polynav.geometry import Pose2D
from polynav.nav.retry_budget import RetryBudget


def _budget() -> RetryBudget:
    return RetryBudget(max_retries=2, radius=1.0, min_time=10.0)


def test_failures_left_behind_on_the_way_to_the_goal_are_forgotten() -> None:
    budget = _budget()
    assert budget.record(Pose2D(0.0, 0.0), 10.0, now=0.0) == 1
    assert budget.record(Pose2D(0.1, 0.0), 9.9, now=1.0) == 2
    # 2 m on and 2 m nearer the goal: a new place, the ladder starts again.
    assert budget.record(Pose2D(2.0, 0.0), 8.0, now=2.0) == 1


def test_swinging_between_two_blocked_sides_counts_on_and_gives_up() -> None:
    budget = _budget()
    sides = (Pose2D(0.0, 1.5), Pose2D(0.0, -1.5))  # both 10 m from the goal, 3 m apart
    rungs = [budget.record(sides[i % 2], 10.0, now=float(5 * i)) for i in range(4)]
    assert rungs == [1, 2, 3, 4]
    assert budget.exhausted(now=15.0)


def test_a_place_is_given_up_only_after_min_time() -> None:
    budget = _budget()
    for i in range(4):
        budget.record(Pose2D(0.0, 0.0), 10.0, now=float(i))
    assert not budget.exhausted(now=3.0)
    assert budget.exhausted(now=10.0)


def test_no_retries_asked_gives_up_at_the_first_failure() -> None:
    budget = _budget()
    budget.reset(max_retries=0)
    budget.record(Pose2D(0.0, 0.0), 10.0, now=0.0)
    assert budget.exhausted(now=0.0)
