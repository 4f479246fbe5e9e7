from __future__ import annotations

import math

import pytest

from polynav.geometry import (
    Pose2D,
    angle_diff,
    quaternion_to_yaw,
    wrap_angle,
    yaw_to_quaternion,
)


@pytest.mark.parametrize(
    ("angle", "expected"),
    [
        (0.0, 0.0),
        (math.pi, math.pi),
        (-math.pi, math.pi),
        (3 * math.pi, math.pi),
        (2 * math.pi, 0.0),
        (-0.5, -0.5),
        (7.0, 7.0 - 2 * math.pi),
        (-7.0, -7.0 + 2 * math.pi),
    ],
)
def test_wrap_angle_lands_in_half_open_interval(angle: float, expected: float) -> None:
    assert wrap_angle(angle) == pytest.approx(expected, abs=1e-12)
    assert -math.pi < wrap_angle(angle) <= math.pi


def test_angle_diff_takes_the_short_way_round() -> None:
    assert angle_diff(math.radians(170), math.radians(-170)) == pytest.approx(math.radians(-20))
    assert angle_diff(math.radians(-170), math.radians(170)) == pytest.approx(math.radians(20))


@pytest.mark.parametrize("yaw", [0.0, 0.3, -1.2, math.pi, -math.pi + 1e-9, 2.5])
def test_quaternion_round_trip(yaw: float) -> None:
    q = yaw_to_quaternion(yaw)
    assert math.sqrt(sum(c * c for c in q)) == pytest.approx(1.0)
    assert quaternion_to_yaw(*q) == pytest.approx(wrap_angle(yaw), abs=1e-12)


def test_quaternion_to_yaw_accepts_unnormalised_input() -> None:
    x, y, z, w = yaw_to_quaternion(0.7)
    assert quaternion_to_yaw(3 * x, 3 * y, 3 * z, 3 * w) == pytest.approx(0.7)


def test_pose_theta_is_wrapped_on_construction() -> None:
    assert Pose2D(0, 0, 3 * math.pi).theta == pytest.approx(math.pi)


def test_compose_then_inverse_is_identity() -> None:
    a = Pose2D(1.0, -2.0, 0.8)
    b = Pose2D(-0.3, 0.5, -2.9)
    back = a.compose(b).relative_to(a)
    assert (back.x, back.y, back.theta) == pytest.approx((b.x, b.y, b.theta))
    ident = a.compose(a.inverse())
    assert (ident.x, ident.y, ident.theta) == pytest.approx((0.0, 0.0, 0.0), abs=1e-12)


def test_compose_moves_in_the_parent_frame() -> None:
    robot = Pose2D(2.0, 1.0, math.pi / 2)
    ahead = robot.compose(Pose2D(1.0, 0.0, 0.0))
    assert (ahead.x, ahead.y, ahead.theta) == pytest.approx((2.0, 2.0, math.pi / 2))
    assert robot.transform_point(0.0, 1.0) == pytest.approx((1.0, 1.0))


def test_distance_and_heading_error() -> None:
    a = Pose2D(0.0, 0.0, 0.1)
    b = Pose2D(3.0, 4.0, -0.1)
    assert a.distance_to(b) == pytest.approx(5.0)
    assert a.heading_error_to(b) == pytest.approx(-0.2)
