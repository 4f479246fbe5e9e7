from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.geometry import Pose2D, Twist
from polynav.robot.sim.config import SimConfig
from polynav.robot.sim.odometry import WheelOdometry


def _drive(seed: int, steps: int = 250, config: SimConfig | None = None) -> WheelOdometry:
    """5 m straight ahead (0.02 m per step) from where the odometry starts."""
    odom = WheelOdometry(config or SimConfig(), np.random.default_rng(seed))
    for k in range(steps):
        odom.update(0.02, 0.0, 0.02, (k + 1) * 0.02)
    return odom


def test_odometry_starts_at_zero_as_a_base_switched_on() -> None:
    odom = WheelOdometry(SimConfig(), np.random.default_rng(0), stamp=4.0)
    assert odom.reading.pose == Pose2D(0.0, 0.0, 0.0)
    assert odom.reading.stamp == 4.0
    assert odom.reading.twist == Twist()


def test_noise_free_odometry_follows_the_motion_exactly() -> None:
    config = SimConfig(odom_translation_noise=0.0, odom_rotation_noise=0.0,
                       odom_translation_additive=0.0, odom_rotation_additive=0.0)
    odom = WheelOdometry(config, np.random.default_rng(0))
    for k in range(100):
        odom.update(0.01, math.pi / 200, 0.02, (k + 1) * 0.02)
    # A quarter circle of length 1 m to the left: radius 2/pi, ending facing +y.
    pose = odom.reading.pose
    r = 2.0 / math.pi
    assert (pose.x, pose.y) == pytest.approx((r, r), abs=1e-12)
    assert pose.theta == pytest.approx(math.pi / 2)
    assert odom.reading.twist.linear == pytest.approx(0.5)
    assert odom.reading.stamp == pytest.approx(2.0)


def test_odometry_drifts_but_stays_close_over_a_short_drive() -> None:
    odom = _drive(seed=3)
    truth = Pose2D(5.0, 0.0, 0.0)
    error = odom.reading.pose.distance_to(truth)
    assert 0.0 < error < 0.05
    assert 0.0 < abs(odom.reading.pose.heading_error_to(truth)) < 0.02
    assert odom.reading.twist.linear != 1.0


def test_a_standing_base_reads_no_motion() -> None:
    odom = _drive(seed=3, steps=10)
    before = odom.reading.pose
    for k in range(100):
        odom.update(0.0, 0.0, 0.02, 1.0 + k * 0.02)
    assert odom.reading.pose == before
    assert odom.reading.twist == Twist()


def test_same_seed_same_drift_and_another_seed_differs() -> None:
    assert _drive(seed=5).reading.pose == _drive(seed=5).reading.pose
    assert _drive(seed=5).reading.pose != _drive(seed=6).reading.pose
