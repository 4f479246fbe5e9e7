from __future__ import annotations

import math

import pytest

from polynav.control.interface import ControlStatus
from polynav.control.progress_checker import ProgressChecker, ProgressCheckerConfig
from polynav.control.pure_pursuit import RegulatedPurePursuit
from polynav.errors import ConfigError
from polynav.geometry import Pose2D, Twist
from tests.unit.control.unicycle import DT, empty_grid, polyline, step

CFG = ProgressCheckerConfig(required_movement_radius=0.5, movement_time_allowance=10.0)


def test_stuck_only_once_the_allowance_has_passed() -> None:
    checker = ProgressChecker(CFG)
    checker.reset(Pose2D(), 0.0)
    assert checker.check(Pose2D(0.4, 0.0, 0.0), 9.99)
    assert not checker.check(Pose2D(0.4, 0.0, 0.0), 10.0)


def test_leaving_the_circle_restarts_the_allowance() -> None:
    checker = ProgressChecker(CFG)
    checker.reset(Pose2D(), 0.0)
    assert checker.check(Pose2D(0.5, 0.0, 0.0), 9.0)
    assert checker.check(Pose2D(0.6, 0.0, 0.0), 18.9)
    assert not checker.check(Pose2D(0.6, 0.0, 0.0), 19.0)


def test_first_check_starts_the_clock() -> None:
    checker = ProgressChecker(CFG)
    assert checker.check(Pose2D(), 100.0)
    assert checker.check(Pose2D(), 109.9)
    assert not checker.check(Pose2D(), 110.0)


def test_a_turn_of_the_required_angle_counts_as_progress() -> None:
    checker = ProgressChecker(CFG)
    checker.reset(Pose2D(), 0.0)
    assert checker.check(Pose2D(0.0, 0.0, 0.5), 9.0)  # restarted at t = 9
    assert checker.check(Pose2D(0.0, 0.0, 0.6), 18.9)
    assert not checker.check(Pose2D(0.0, 0.0, 0.6), 19.0)


def test_wobbling_in_place_is_not_progress() -> None:
    checker = ProgressChecker(CFG)
    checker.reset(Pose2D(), 0.0)
    now = 0.0
    results = []
    for k in range(21):
        now = 0.5 * k
        results.append(checker.check(Pose2D(0.01 * (k % 2), 0.0, 0.4 * (-1) ** k), now))
    assert all(results[:-1]) and not results[-1]


def test_turning_can_be_switched_off() -> None:
    checker = ProgressChecker(ProgressCheckerConfig(required_movement_angle=math.inf))
    checker.reset(Pose2D(), 0.0)
    assert checker.check(Pose2D(0.0, 0.0, 3.0), 5.0)
    assert not checker.check(Pose2D(0.0, 0.0, -3.0), 10.0)


def test_robot_pressing_against_an_obstacle_is_stuck_after_the_allowance_in_sim_time() -> None:
    # The controller drives the robot into a low box it cannot see at x = 1; the wheels slip and
    # the robot stays put. Sim time advances by DT per period.
    ctrl = RegulatedPurePursuit()
    ctrl.set_path(polyline((0.0, 0.0), (6.0, 0.0)), Pose2D(6.0, 0.0, 0.0))
    checker = ProgressChecker(CFG)
    grid = empty_grid()
    pose, velocity, now = Pose2D(), Twist(), 0.0
    checker.reset(pose, now)
    reference, reference_time = pose, now  # kept here independently of the checker
    answers: list[tuple[float, bool]] = []
    while now < 30.0:
        cmd = ctrl.compute(pose, velocity, grid, DT)
        assert cmd.status is ControlStatus.TRACKING
        moved = step(pose, cmd.twist)
        pose, velocity = (moved, cmd.twist) if moved.x < 1.0 else (pose, Twist())
        now += DT
        if pose.distance_to(reference) >= CFG.required_movement_radius:
            reference, reference_time = pose, now
        answers.append((now, checker.check(pose, now)))
    assert 0.5 <= reference.x < 1.0  # the last progress was on the way to the box
    deadline = reference_time + CFG.movement_time_allowance
    assert all(ok for t, ok in answers if t < deadline - 1e-9)
    assert not any(ok for t, ok in answers if t >= deadline - 1e-9)
    assert any(t >= deadline for t, _ in answers)


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("required_movement_radius", 0.0),
        ("movement_time_allowance", -1.0),
        ("required_movement_angle", 0.0),
        ("required_movement_angle", 4.0),
    ],
)
def test_config_rejects_bad_values(field: str, value: float) -> None:
    with pytest.raises(ConfigError) as err:
        ProgressCheckerConfig(**{field: value})
    assert err.value.key == f"control.progress_checker.{field}"
