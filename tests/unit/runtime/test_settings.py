from __future__ import annotations

import math

import pytest

from polynav.errors import ConfigError, InvalidRequest
from polynav.runtime.settings import SETTING_RANGES, RobotSettings


def test_defaults_lie_within_their_ranges() -> None:
    s = RobotSettings()
    for key, (lo, hi) in SETTING_RANGES.items():
        assert lo <= getattr(s, key) <= hi, key
    assert set(SETTING_RANGES) == set(s.to_dict())


def test_apply_returns_new_settings_and_leaves_the_old_unchanged() -> None:
    s = RobotSettings()
    new = s.apply({"max_linear_velocity": 0.3, "low_battery_percent": 25})
    assert new.max_linear_velocity == 0.3
    assert new.low_battery_percent == 25.0
    assert s.max_linear_velocity == 0.6


@pytest.mark.parametrize(
    ("changes", "field"),
    [
        ({"max_linear_velocity": 3.5}, "max_linear_velocity"),
        ({"max_linear_velocity": 0.0}, "max_linear_velocity"),
        ({"robot_radius": -0.1}, "robot_radius"),
        ({"yaw_goal_tolerance": math.nan}, "yaw_goal_tolerance"),
        ({"xy_goal_tolerance": math.inf}, "xy_goal_tolerance"),
        ({"max_angular_velocity": "fast"}, "max_angular_velocity"),
        ({"max_angular_velocity": True}, "max_angular_velocity"),
        ({"max_speed": 1.0}, "max_speed"),
        ({"obstacle_stop_distance": 1.6}, "obstacle_stop_distance"),
        ({"critical_battery_percent": 30.0}, "critical_battery_percent"),
    ],
)
def test_apply_refuses_bad_values_naming_the_field(changes: dict[str, object], field: str) -> None:
    with pytest.raises(InvalidRequest) as info:
        RobotSettings().apply(changes)
    assert info.value.field == field


def test_a_bad_change_applies_nothing_of_the_batch() -> None:
    s = RobotSettings()
    with pytest.raises(InvalidRequest):
        s.apply({"max_linear_velocity": 0.3, "robot_radius": 5.0})
    assert s == RobotSettings()


def test_constructing_out_of_range_settings_is_a_config_error() -> None:
    with pytest.raises(ConfigError) as info:
        RobotSettings(robot_radius=2.0)
    assert info.value.key == "runtime.settings.robot_radius"


def test_from_stored_skips_unknown_and_invalid_values() -> None:
    s = RobotSettings.from_stored({"max_linear_velocity": 9.0, "legacy": 1, "robot_radius": 0.3})
    assert s == RobotSettings(robot_radius=0.3)


def test_stack_config_carries_the_settings_into_controller_and_costmap() -> None:
    s = RobotSettings().apply({
        "max_linear_velocity": 0.3, "max_angular_velocity": 0.8, "xy_goal_tolerance": 0.1,
        "yaw_goal_tolerance": 0.2, "robot_radius": 0.4, "obstacle_slowdown_distance": 2.0,
        "obstacle_stop_distance": 0.5,
    })
    config = s.stack_config()
    c = config.controller
    assert (c.max_linear_velocity, c.max_angular_velocity) == (0.3, 0.8)
    assert (c.xy_goal_tolerance, c.yaw_goal_tolerance) == (0.1, 0.2)
    assert (c.slowdown_distance, c.min_stop_distance) == (2.0, 0.5)
    assert config.costmap.robot_radius == 0.4
    assert config.costmap.inflation_radius == pytest.approx(0.7)


def test_stack_config_is_valid_at_the_slowest_speeds() -> None:
    s = RobotSettings().apply({"max_linear_velocity": 0.1, "max_angular_velocity": 0.2})
    config = s.stack_config()
    assert config.controller.min_regulated_speed <= 0.1
    assert config.controller.min_rotation_speed <= 0.2
