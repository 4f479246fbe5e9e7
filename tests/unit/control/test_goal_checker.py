from __future__ import annotations

import math

import pytest

from polynav.control.goal_checker import GoalChecker
from polynav.errors import ConfigError
from polynav.geometry import Pose2D

GOAL = Pose2D(1.0, 1.0, 0.0)


def test_position_is_latched_so_jitter_while_turning_does_not_undo_it() -> None:
    checker = GoalChecker(xy_tolerance=0.05, yaw_tolerance=0.05)
    assert not checker.is_reached(Pose2D(1.0, 0.9, 0.0), GOAL)
    assert not checker.xy_reached
    # Within tolerance but facing away: position latched, goal not reached yet.
    assert not checker.is_reached(Pose2D(1.0, 0.96, 1.0), GOAL)
    assert checker.xy_reached
    # The estimate jitters 10 cm away while the robot finishes its turn: still reached.
    assert checker.is_reached(Pose2D(1.0, 0.90, 0.04), GOAL)


def test_heading_is_never_latched() -> None:
    checker = GoalChecker(xy_tolerance=0.05, yaw_tolerance=0.05)
    assert checker.is_reached(Pose2D(1.0, 1.0, 0.0), GOAL)
    assert not checker.is_reached(Pose2D(1.0, 1.0, 0.2), GOAL)
    assert checker.heading_reached(Pose2D(1.0, 1.0, -0.05), GOAL)


def test_reset_forgets_the_latch() -> None:
    checker = GoalChecker()
    checker.latch()
    assert checker.is_reached(Pose2D(1.0, 0.5, 0.0), GOAL)
    checker.reset()
    assert not checker.xy_reached
    assert not checker.is_reached(Pose2D(1.0, 0.5, 0.0), GOAL)


def test_tolerance_boundary_counts_as_reached() -> None:
    checker = GoalChecker(xy_tolerance=0.25, yaw_tolerance=0.5)
    assert checker.position_reached(Pose2D(1.0, 0.75, 0.0), GOAL)
    assert checker.heading_reached(Pose2D(1.0, 1.0, 0.5), GOAL)


def test_heading_error_wraps_around_pi() -> None:
    checker = GoalChecker()
    goal = Pose2D(0.0, 0.0, math.pi)
    assert checker.is_reached(Pose2D(0.0, 0.0, -math.pi + 0.01), goal)


@pytest.mark.parametrize(
    ("xy", "yaw", "key"),
    [(0.0, 0.05, "xy_tolerance"), (0.05, -0.1, "yaw_tolerance"), (math.nan, 0.05, "xy_tolerance")],
)
def test_non_positive_tolerances_are_rejected(xy: float, yaw: float, key: str) -> None:
    with pytest.raises(ConfigError) as err:
        GoalChecker(xy, yaw)
    assert err.value.key == f"control.goal_checker.{key}"
