from __future__ import annotations

import math

import pytest

from polynav.errors import ConfigError
from polynav.robot.sim.config import SimConfig


def test_defaults_are_valid_and_step_at_fifty_hertz() -> None:
    config = SimConfig()
    assert config.physics_period == pytest.approx(0.02)
    assert config.linear_deceleration > config.linear_acceleration


@pytest.mark.parametrize(
    ("changes", "key"),
    [
        ({"robot_radius": 0.0}, "sim.robot_radius"),
        ({"linear_deceleration": -1.0}, "sim.linear_deceleration"),
        ({"lidar_range_noise": -0.01}, "sim.lidar_range_noise"),
        ({"lidar_beams": 0}, "sim.lidar_beams"),
        ({"lidar_beams": 2.5}, "sim.lidar_beams"),
        ({"lidar_fov": 7.0}, "sim.lidar_fov"),
        ({"lidar_range_min": 12.0}, "sim.lidar_range_min"),
        ({"lidar_rate": 60.0}, "sim.lidar_rate"),
        ({"imu_rate": 100.0}, "sim.imu_rate"),
        ({"battery_start_percent": 101.0}, "sim.battery_start_percent"),
        ({"battery_empty_voltage": 30.0}, "sim.battery_empty_voltage"),
        ({"max_linear_velocity": math.inf}, "sim.max_linear_velocity"),
        ({"odom_rotation_noise": math.nan}, "sim.odom_rotation_noise"),
    ],
)
def test_out_of_range_value_is_rejected_naming_its_key(changes: dict[str, float], key: str
                                                       ) -> None:
    with pytest.raises(ConfigError) as error:
        SimConfig(**changes)  # type: ignore[arg-type]
    assert error.value.key == key
