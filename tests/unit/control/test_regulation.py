from __future__ import annotations

import math

import pytest

from polynav.control import regulation
from polynav.maps import costs


def test_lookahead_grows_with_speed_within_bounds() -> None:
    kw = {"lookahead_time": 1.5, "min_lookahead": 0.3, "max_lookahead": 0.9}
    assert regulation.lookahead_distance(0.0, **kw) == 0.3
    assert regulation.lookahead_distance(0.4, **kw) == pytest.approx(0.6)
    assert regulation.lookahead_distance(-0.4, **kw) == pytest.approx(0.6)
    assert regulation.lookahead_distance(0.7, **kw) == 0.9


def test_curvature_is_two_y_over_l_squared() -> None:
    assert regulation.curvature(1.0, 0.0) == 0.0
    assert regulation.curvature(0.0, 0.5) == pytest.approx(4.0)  # half circle of radius 0.25
    assert regulation.curvature(0.6, -0.8) == pytest.approx(-1.6)
    assert regulation.curvature(0.0, 0.0) == 0.0


def test_curvature_regulation_slows_only_tighter_arcs() -> None:
    assert regulation.curvature_speed(0.6, 1.0 / 1.8, min_radius=0.9) == 0.6
    assert regulation.curvature_speed(0.6, -1.0 / 0.45, min_radius=0.9) == pytest.approx(0.3)
    assert regulation.curvature_speed(0.6, 0.0, min_radius=0.9) == 0.6


def test_proximity_factor_falls_linearly_above_the_threshold() -> None:
    kw = {"cost_threshold": 128, "slowdown": 0.5}
    assert regulation.proximity_factor(0, **kw) == 1.0
    assert regulation.proximity_factor(128, **kw) == 1.0
    assert regulation.proximity_factor(190, **kw) == pytest.approx(0.75)
    assert regulation.proximity_factor(252, **kw) == pytest.approx(0.5)
    assert regulation.proximity_factor(costs.INSCRIBED, **kw) == pytest.approx(0.5)
    assert regulation.proximity_factor(costs.LETHAL, **kw) == pytest.approx(0.5)
    assert regulation.proximity_factor(costs.UNKNOWN, **kw) == 1.0


def test_approach_speed_scales_with_the_remaining_distance_down_to_a_floor() -> None:
    kw = {"scaling_distance": 0.6, "min_speed": 0.05}
    assert regulation.approach_speed(0.6, 1.0, **kw) == 0.6
    assert regulation.approach_speed(0.6, 0.3, **kw) == pytest.approx(0.3)
    assert regulation.approach_speed(0.2, 0.3, **kw) == pytest.approx(0.1)
    assert regulation.approach_speed(0.6, 0.01, **kw) == 0.05
    assert regulation.approach_speed(0.03, 0.01, **kw) == 0.03  # never faster than asked


def test_stop_distance_is_lookahead_travel_plus_braking_with_a_floor() -> None:
    kw = {"deceleration": 1.2, "lookahead_time": 1.0, "minimum": 0.35}
    assert regulation.stop_distance(0.6, **kw) == pytest.approx(0.6 + 0.15)
    assert regulation.stop_distance(0.1, **kw) == 0.35
    assert regulation.stop_distance(-0.6, **kw) == pytest.approx(0.75)


def test_obstacle_speed_falls_from_the_slowdown_to_the_stop_distance() -> None:
    kw = {"stop_at": 0.5, "slowdown_distance": 1.5, "max_speed": 0.6, "min_speed": 0.1}
    assert regulation.obstacle_speed(2.0, **kw) == 0.6
    assert regulation.obstacle_speed(1.0, **kw) == pytest.approx(0.3)
    assert regulation.obstacle_speed(0.55, **kw) == 0.1
    # A stop distance beyond the slowdown distance (at high speed): no slowdown band.
    assert regulation.obstacle_speed(1.0, **{**kw, "stop_at": 1.6}) == 0.6


def test_rotation_speed_stops_on_the_heading() -> None:
    kw = {"max_speed": 1.5, "acceleration": 3.0, "gain": 2.5, "min_speed": 0.1}
    assert regulation.rotation_speed(3.0, **kw) == 1.5
    assert regulation.rotation_speed(-0.2, **kw) == pytest.approx(-0.5)  # gain bound
    assert regulation.rotation_speed(0.5, **kw) == pytest.approx(1.25)  # gain < sqrt(2 a e)
    assert regulation.rotation_speed(0.01, **kw) == 0.1
    assert regulation.rotation_speed(-0.01, **kw) == -0.1
    assert regulation.rotation_speed(0.0, **kw) == 0.0
    # Near the end the deceleration needed is at most the limit.
    e = 0.3
    w = regulation.rotation_speed(e, **{**kw, "gain": 100.0})
    assert w == pytest.approx(math.sqrt(2 * 3.0 * e))


def test_linear_limit_speeds_up_and_brakes_at_their_own_rates() -> None:
    kw = {"acceleration": 0.8, "deceleration": 1.2, "dt": 0.05}
    assert regulation.limit_linear(0.6, 0.0, **kw) == pytest.approx(0.04)
    assert regulation.limit_linear(0.0, 0.6, **kw) == pytest.approx(0.54)
    assert regulation.limit_linear(0.3, 0.31, **kw) == 0.3
    assert regulation.limit_linear(0.0, -0.2, **kw) == pytest.approx(-0.14)
    assert regulation.limit_linear(-0.6, -0.2, **kw) == pytest.approx(-0.24)
    assert regulation.limit_linear(0.5, 0.0, **{**kw, "dt": 0.0}) == 0.5


def test_angular_limit() -> None:
    assert regulation.limit_angular(1.5, 0.0, acceleration=3.0, dt=0.05) == pytest.approx(0.15)
    assert regulation.limit_angular(-1.5, 1.0, acceleration=3.0, dt=0.05) == pytest.approx(0.85)
    assert regulation.limit_angular(0.1, 0.0, acceleration=3.0, dt=0.05) == 0.1


def test_approach_speed_lets_a_fast_base_brake_before_the_goal() -> None:
    kw = {"scaling_distance": 0.6, "min_speed": 0.05, "deceleration": 2.0}
    share = regulation.APPROACH_BRAKING_SHARE
    assert regulation.approach_speed(2.0, 3.0, **kw) == 2.0  # far: full speed
    one_metre = regulation.approach_speed(2.0, 1.0, **kw)
    assert one_metre == pytest.approx((2.0 * share * 2.0 * 1.0) ** 0.5)
    assert one_metre**2 / (2.0 * 2.0) < 1.0  # it can stop within the metre left
    assert regulation.approach_speed(2.0, 0.0, **kw) == 0.05
    # A slow robot is held by the ramp alone, as before.
    assert regulation.approach_speed(0.6, 0.3, **kw) == pytest.approx(0.3)
