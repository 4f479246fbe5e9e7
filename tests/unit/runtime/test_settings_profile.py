"""Settings held to the robot's profile: no speed above its limits, no planning footprint below
its body; defaults and the stack built from the profile."""

from __future__ import annotations

import pytest

from polynav.nav.stack import stack_config_for
from polynav.robot.profile import load_profile
from polynav.runtime.settings import BeyondProfile, RobotSettings

DEMO = load_profile("demo")
BASE = load_profile("research-base")


def test_planning_footprint_below_the_body_is_refused() -> None:
    with pytest.raises(BeyondProfile) as err:
        RobotSettings().apply({"robot_radius": 0.1}, DEMO)
    assert err.value.field == "robot_radius"
    assert "below the body" in str(err.value)
    # At or above the body is fine, and without a profile only the range applies.
    assert RobotSettings().apply({"robot_radius": 0.25}, DEMO).robot_radius == 0.25
    assert RobotSettings().apply({"robot_radius": 0.1}).robot_radius == 0.1


def test_speeds_above_the_profile_are_refused() -> None:
    with pytest.raises(BeyondProfile, match="limits.max_linear_velocity"):
        RobotSettings().apply({"max_linear_velocity": 1.2}, DEMO)
    with pytest.raises(BeyondProfile, match="limits.max_angular_velocity"):
        RobotSettings().apply({"max_angular_velocity": 2.5}, DEMO)
    fast = RobotSettings.defaults_for(BASE).apply({"max_linear_velocity": 1.9}, BASE)
    assert fast.max_linear_velocity == 1.9


def test_defaults_follow_the_profile() -> None:
    assert RobotSettings.defaults_for(DEMO) == RobotSettings()
    base = RobotSettings.defaults_for(BASE)
    assert base.max_linear_velocity == 2.0
    assert base.robot_radius == pytest.approx(0.215)


def test_stored_settings_the_profile_forbids_fall_back_to_its_defaults() -> None:
    s = RobotSettings.from_stored({"max_linear_velocity": 1.8, "robot_radius": 0.12}, DEMO)
    assert s == RobotSettings()


def test_stack_is_built_from_the_profile_and_then_the_settings() -> None:
    config = RobotSettings.defaults_for(BASE).stack_config(stack_config_for(BASE))
    assert config.controller.max_linear_velocity == 2.0
    assert config.controller.linear_acceleration == BASE.cruise.linear_acceleration
    assert config.costmap.robot_radius == pytest.approx(BASE.inscribed_radius)
    assert config.costmap.inflation_radius >= BASE.circumscribed_radius
