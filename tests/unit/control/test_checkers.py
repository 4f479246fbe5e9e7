from __future__ import annotations

import math

import pytest

from polynav.control.goal_checker import GoalChecker, GoalCheckerConfig
from polynav.control.progress_checker import ProgressChecker, ProgressCheckerConfig
from polynav.errors import ConfigError
from polynav.geometry import Pose2D


def test_progress_checker_declares_stuck_only_after_the_allowance() -> None:
    checker = ProgressChecker(ProgressCheckerConfig(required_movement_radius=0.5,
                                                    movement_time_allowance=10.0))
    checker.reset(Pose2D(), 0.0)
    assert checker.check(Pose2D(0.4, 0.0, 0.0), 9.99)
    assert not checker.check(Pose2D(0.4, 0.0, 0.0), 10.0)


def test_progress_checker_restarts_when_the_robot_moves_on() -> None:
    checker = ProgressChecker(ProgressCheckerConfig(required_movement_radius=0.5,
                                                    movement_time_allowance=10.0))
    checker.reset(Pose2D(), 0.0)
    assert checker.check(Pose2D(0.5, 0.0, 0.0), 9.0)
    assert checker.check(Pose2D(0.6, 0.0, 0.0), 18.9)
    assert not checker.check(Pose2D(0.6, 0.0, 0.0), 19.0)


def test_progress_checker_first_check_starts_the_clock() -> None:
    checker = ProgressChecker()
    assert checker.check(Pose2D(), 100.0)
    assert not checker.check(Pose2D(), 110.0)


def test_goal_checker_latches_position() -> None:
    checker = GoalChecker(GoalCheckerConfig(xy_tolerance=0.05, yaw_tolerance=0.05))
    goal = Pose2D(1.0, 1.0, 0.0)
    assert not checker.is_reached(Pose2D(1.0, 0.9, 0.0), goal)
    assert not checker.is_reached(Pose2D(1.0, 0.96, 1.0), goal)
    assert checker.xy_reached
    assert checker.is_reached(Pose2D(1.0, 0.90, 0.04), goal)
    checker.reset()
    assert not checker.is_reached(Pose2D(1.0, 0.90, 0.04), goal)


def test_goal_checker_heading_wraps() -> None:
    checker = GoalChecker()
    goal = Pose2D(0.0, 0.0, math.pi)
    assert checker.is_reached(Pose2D(0.0, 0.0, -math.pi + 0.01), goal)


@pytest.mark.parametrize(
    ("factory", "key"),
    [(lambda: ProgressCheckerConfig(required_movement_radius=0.0), "required_movement_radius"),
     (lambda: ProgressCheckerConfig(movement_time_allowance=-1.0), "movement_time_allowance"),
     (lambda: GoalCheckerConfig(xy_tolerance=0.0), "xy_tolerance")],
)
def test_configs_reject_bad_values(factory, key: str) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(ConfigError, match=key):
        factory()
