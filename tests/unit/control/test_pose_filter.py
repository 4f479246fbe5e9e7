from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.control.pose_filter import PoseFilter
from polynav.geometry import Pose2D, Twist
from tests.unit.control.unicycle import DT, step


def test_motion_passes_without_lag() -> None:
    smoother = PoseFilter(0.2, 0.2)
    pose, twist = Pose2D(1.0, 2.0, 0.3), Twist(0.5, 0.4)
    for _ in range(100):
        out = smoother.update(pose, twist, DT)
        assert out.distance_to(pose) < 1e-9 and abs(out.heading_error_to(pose)) < 1e-9
        pose = step(pose, twist)


def test_white_noise_is_reduced_about_threefold() -> None:
    rng = np.random.default_rng(7)
    smoother = PoseFilter(0.2, 0.2)
    pose, twist = Pose2D(), Twist(0.3, 0.1)
    raw, smoothed = [], []
    for _ in range(2000):
        seen = Pose2D(pose.x + rng.normal(0, 0.01), pose.y + rng.normal(0, 0.01), pose.theta)
        out = smoother.update(seen, twist, DT)
        raw.append(seen.x - pose.x)
        smoothed.append(out.x - pose.x)
        pose = step(pose, twist)
    ratio = np.std(raw[50:]) / np.std(smoothed[50:])
    assert ratio == pytest.approx(3.0, rel=0.15)


def test_a_correction_is_followed_within_a_few_periods() -> None:
    smoother = PoseFilter(0.2, 0.2)
    smoother.update(Pose2D(), Twist(), DT)
    out = Pose2D()
    for _ in range(20):
        out = smoother.update(Pose2D(0.1, 0.0, 0.0), Twist(), DT)
    assert out.x == pytest.approx(0.1 * (1 - 0.8**20))


def test_a_jump_beyond_the_reset_distance_is_taken_at_once() -> None:
    smoother = PoseFilter(0.2, 0.2)
    smoother.update(Pose2D(), Twist(), DT)
    assert smoother.update(Pose2D(0.5, 0.0, 1.0), Twist(), DT) == Pose2D(0.5, 0.0, 1.0)


def test_heading_is_blended_across_pi() -> None:
    smoother = PoseFilter(0.5, 0.2)
    smoother.update(Pose2D(0.0, 0.0, math.pi - 0.1), Twist(), DT)
    out = smoother.update(Pose2D(0.0, 0.0, -math.pi + 0.1), Twist(), DT)
    assert abs(out.theta) == pytest.approx(math.pi)


def test_gain_one_and_reset_pass_the_estimate_through() -> None:
    raw = PoseFilter(1.0, 0.2)
    raw.update(Pose2D(), Twist(), DT)
    assert raw.update(Pose2D(0.05, 0.0, 0.0), Twist(), DT) == Pose2D(0.05, 0.0, 0.0)
    smoother = PoseFilter(0.2, 0.2)
    smoother.update(Pose2D(), Twist(), DT)
    smoother.reset()
    assert smoother.update(Pose2D(0.05, 0.0, 0.0), Twist(), DT) == Pose2D(0.05, 0.0, 0.0)
