"""The simulated planar IMU: a gyro with white noise and a constant bias, and an accelerometer.

The gyro's bias is drawn once per run (from the IMU's own noise stream), so the integrated yaw
drifts steadily, as a real MEMS gyro's does, while the turn rate it reports is the truth plus
bias plus white noise. Yaw starts at the start pose's heading and integrates the true heading
change between samples plus ``(bias + noise) * interval``; like odometry, it does not see a
teleport. The acceleration is the base's forward acceleration over the last physics step.
"""

from __future__ import annotations

import logging

import numpy as np

from polynav.geometry import wrap_angle
from polynav.robot.interface import ImuReading
from polynav.robot.sim.config import SimConfig

log = logging.getLogger(__name__)


class Imu:
    """A gyro and forward accelerometer sampled at ``imu_rate``."""

    def __init__(self, config: SimConfig, start_yaw: float, rng: np.random.Generator,
                 stamp: float = 0.0) -> None:
        self._config = config
        self._rng = rng
        self.bias = float(config.imu_yaw_rate_bias * rng.standard_normal())
        self._yaw = start_yaw
        self._turned = 0.0
        self._last_stamp = stamp
        self._reading: ImuReading | None = None

    @property
    def reading(self) -> ImuReading | None:
        """The newest sample, or ``None`` before the first."""
        return self._reading

    def accumulate(self, rotation: float) -> None:
        """Add one physics step's true heading change [rad]."""
        self._turned += rotation

    def sample(self, angular_velocity: float, linear_acceleration: float, stamp: float) -> None:
        """Take a sample at ``stamp`` [s] of the true turn rate [rad/s] and acceleration [m/s²]."""
        c = self._config
        n = self._rng.standard_normal(2).tolist()
        rate_error = self.bias + c.imu_yaw_rate_noise * n[0]
        interval = stamp - self._last_stamp
        self._yaw = wrap_angle(self._yaw + self._turned + rate_error * interval)
        self._turned = 0.0
        self._last_stamp = stamp
        self._reading = ImuReading(
            stamp=stamp,
            yaw=self._yaw,
            angular_velocity=angular_velocity + rate_error,
            linear_acceleration=linear_acceleration + c.imu_acceleration_noise * n[1],
        )
