from __future__ import annotations

import numpy as np
import pytest

from polynav.robot.sim.config import SimConfig
from polynav.robot.sim.imu import Imu


def test_no_reading_before_the_first_sample() -> None:
    assert Imu(SimConfig(), 0.0, np.random.default_rng(0)).reading is None


def test_noise_free_imu_integrates_the_true_turn() -> None:
    config = SimConfig(imu_yaw_rate_noise=0.0, imu_yaw_rate_bias=0.0,
                       imu_acceleration_noise=0.0)
    imu = Imu(config, 1.0, np.random.default_rng(0))
    for k in range(50):
        imu.accumulate(0.01)
        imu.sample(0.5, 0.2, (k + 1) * 0.02)
    reading = imu.reading
    assert reading is not None
    assert reading.yaw == pytest.approx(1.5)
    assert (reading.angular_velocity, reading.linear_acceleration) == (0.5, 0.2)
    assert reading.stamp == pytest.approx(1.0)


def test_a_standing_gyro_drifts_by_its_bias() -> None:
    config = SimConfig(imu_yaw_rate_noise=0.001, imu_yaw_rate_bias=0.01)
    imu = Imu(config, 0.0, np.random.default_rng(4))
    assert imu.bias != 0.0
    rates = []
    for k in range(3000):  # one minute at 50 Hz
        imu.sample(0.0, 0.0, (k + 1) * 0.02)
        assert imu.reading is not None
        rates.append(imu.reading.angular_velocity)
    assert np.mean(rates) == pytest.approx(imu.bias, abs=1e-4)
    assert imu.reading.yaw == pytest.approx(imu.bias * 60.0, abs=1e-3)
