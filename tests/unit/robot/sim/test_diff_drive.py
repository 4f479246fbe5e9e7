from __future__ import annotations

import math

import pytest

from polynav.geometry import Pose2D, Twist
from polynav.robot.sim.config import SimConfig
from polynav.robot.sim.diff_drive import DiffDrive, integrate_arc, ramp

DT = 0.02


def test_ramp_speeds_up_at_the_acceleration_and_means_the_trapezoid() -> None:
    v, mean = ramp(0.0, 1.0, DT, accel=1.0, decel=2.5)
    assert v == pytest.approx(0.02)
    assert mean == pytest.approx(0.01)


def test_ramp_slows_down_at_the_deceleration() -> None:
    v, mean = ramp(1.0, 0.0, DT, accel=1.0, decel=2.5)
    assert v == pytest.approx(0.95)
    assert mean == pytest.approx(0.975)


def test_ramp_reaches_a_near_target_within_the_step_and_holds_it() -> None:
    # 0.01 m/s short of the target: reached after 0.01 s, then held for the other 0.01 s.
    v, mean = ramp(0.49, 0.5, DT, accel=1.0, decel=2.5)
    assert v == 0.5
    assert mean == pytest.approx((0.495 * 0.01 + 0.5 * 0.01) / DT)


def test_ramp_reversal_brakes_to_zero_then_speeds_up_backwards() -> None:
    # 0.2 s braking from 0.5 at 2.5 (area 0.05), then 0.1 s at 1.0 backwards (area -0.005).
    v, mean = ramp(0.5, -0.5, 0.3, accel=1.0, decel=2.5)
    assert v == pytest.approx(-0.1)
    assert mean == pytest.approx((0.05 - 0.005) / 0.3)


def test_arc_integration_is_exact_for_a_quarter_circle() -> None:
    pose = integrate_arc(Pose2D(1.0, 2.0, 0.0), 1.0, math.pi / 2, 1.0)
    radius = 2.0 / math.pi
    assert pose.x == pytest.approx(1.0 + radius, abs=1e-12)
    assert pose.y == pytest.approx(2.0 + radius, abs=1e-12)
    assert pose.theta == pytest.approx(math.pi / 2, abs=1e-12)


def test_arc_integration_in_many_steps_equals_one_step() -> None:
    start = Pose2D(0.5, -1.0, 2.0)
    pose = start
    for _ in range(100):
        pose = integrate_arc(pose, 0.7, -1.3, 0.01)
    whole = integrate_arc(start, 0.7, -1.3, 1.0)
    assert (pose.x, pose.y, pose.theta) == pytest.approx((whole.x, whole.y, whole.theta),
                                                         abs=1e-12)


def test_straight_line_with_no_turn() -> None:
    pose = integrate_arc(Pose2D(0.0, 0.0, math.pi / 4), 2.0, 0.0, 0.5)
    assert (pose.x, pose.y) == pytest.approx((math.sqrt(0.5), math.sqrt(0.5)), abs=1e-15)


def test_base_respects_acceleration_limits_and_clamps_commands() -> None:
    config = SimConfig()
    base = DiffDrive(config, Pose2D())
    assert base.clamp(Twist(5.0, -9.0)) == Twist(1.0, -2.0)
    speeds = []
    for _ in range(80):
        base.apply(base.propose(Twist(5.0, 9.0), DT))
        speeds.append(base.twist)
    linear = [0.0] + [t.linear for t in speeds]
    angular = [0.0] + [t.angular for t in speeds]
    assert max(b - a for a, b in zip(linear, linear[1:], strict=False)) == pytest.approx(
        config.linear_acceleration * DT)
    assert max(b - a for a, b in zip(angular, angular[1:], strict=False)) == pytest.approx(
        config.angular_acceleration * DT)
    # Top speed after 1.0 s (linear) and 0.667 s (angular), and never above.
    assert linear.index(1.0) == 50
    assert max(linear) == 1.0 and max(angular) == 2.0
    # Distance of the ramp-up: 0.5 m in the first second, exactly v² / 2a.
    base = DiffDrive(config, Pose2D())
    for _ in range(50):
        base.apply(base.propose(Twist(1.0, 0.0), DT))
    assert base.pose.x == pytest.approx(0.5, abs=1e-12)


def test_proposing_changes_nothing_until_applied() -> None:
    base = DiffDrive(SimConfig(), Pose2D())
    step = base.propose(Twist(1.0, 1.0), DT)
    assert base.pose == Pose2D() and base.twist == Twist()
    base.apply(step)
    assert base.pose == step.pose and base.twist == step.twist
    base.halt()
    assert base.twist == Twist() and base.pose == step.pose
