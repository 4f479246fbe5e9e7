from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.errors import Conflict
from polynav.geometry import Pose2D, Twist
from polynav.robot.devices import CalibrationStatus
from polynav.robot.interface import LaserScan, Odometry
from polynav.robot.sim.devices.calibration import (
    IMU_TIME,
    CameraCalibration,
    ImuCalibration,
    LidarCalibration,
)


def _odom(t: float, pose: Pose2D, v: float = 0.3, w: float = 0.0) -> Odometry:
    return Odometry(t, pose, Twist(v, w))


def _scan(t: float, returns: float) -> LaserScan:
    ranges = np.full(100, np.inf, dtype=np.float32)
    ranges[: int(returns * 100)] = 3.0
    return LaserScan(t, -math.pi, 2 * math.pi / 100, 0.1, 10.0, ranges)


def _circle(cal: CameraCalibration | LidarCalibration, t0: float, turns: float,
            radius: float = 1.0, gap: float = 0.0, scan_returns: float = 1.0) -> float:
    """Drive ``turns`` times round a circle (a loop that closes ``gap`` metres off)."""
    steps = int(200 * turns)
    t = t0
    for k in range(steps + 1):
        a = 2 * math.pi * turns * k / steps
        r = radius + gap * a / (2 * math.pi)
        t = t0 + 0.05 * k
        pose = Pose2D(r * math.sin(a), radius - r * math.cos(a), a)
        cal.observe(t, _odom(t, pose, 0.3, 0.3), _scan(t, scan_returns))
    return t


def test_camera_calibration_needs_a_closed_loop_and_then_a_little_more() -> None:
    cal = CameraCalibration()
    assert cal.status() is CalibrationStatus.FREE
    cal.start(0.0)
    assert cal.status() is CalibrationStatus.CALIBRATING
    t = _circle(cal, 0.0, 0.9)  # not closed yet
    assert cal.status() is CalibrationStatus.CALIBRATING and cal.accuracy == 0.0
    _circle(cal, t, 0.3)  # closes (6.3 m), then on for about 1.9 m
    assert cal.status() is CalibrationStatus.CALIBRATED
    assert cal.accuracy == pytest.approx(100.0, abs=5.0)
    cal.complete()
    assert cal.committed and cal.status() is CalibrationStatus.FREE


def test_a_loop_that_does_not_come_back_never_calibrates() -> None:
    cal = CameraCalibration()
    cal.start(0.0)
    _circle(cal, 0.0, 1.5, gap=1.0)  # a spiral: never back within 0.5 m
    assert cal.status() is CalibrationStatus.CALIBRATING


def test_commit_only_when_calibrated_and_cancel_returns_to_free() -> None:
    cal = CameraCalibration()
    with pytest.raises(Conflict):
        cal.complete()
    cal.start(0.0)
    with pytest.raises(Conflict):
        cal.start(1.0)
    with pytest.raises(Conflict):
        cal.complete()
    assert cal.cancel() is True
    assert cal.status() is CalibrationStatus.FREE and not cal.committed
    assert cal.cancel() is False


def test_lidar_calibration_needs_the_camera_first_and_clear_boundaries() -> None:
    camera = CameraCalibration()
    lidar = LidarCalibration(camera)
    with pytest.raises(Conflict, match="camera first"):
        lidar.start(0.0)
    camera.start(0.0)
    _circle(camera, 0.0, 1.3)
    camera.complete()
    lidar.start(100.0)
    _circle(lidar, 100.0, 1.0, scan_returns=0.2)  # open space: nothing counts
    assert lidar.status() is CalibrationStatus.CALIBRATING
    _circle(lidar, 200.0, 0.6, scan_returns=0.9)  # 3.8 m and 3.8 rad with walls in view
    assert lidar.status() is CalibrationStatus.CALIBRATED
    assert lidar.accuracy == pytest.approx(90.0)
    lidar.complete()
    assert lidar.committed and lidar.status() is CalibrationStatus.FREE


def test_imu_calibration_takes_its_time_standing_still_and_fails_if_moved() -> None:
    imu = ImuCalibration()
    with pytest.raises(Conflict, match="still"):
        imu.start(0.0, _odom(0.0, Pose2D(), v=0.2))
    imu.start(0.0, _odom(0.0, Pose2D(), v=0.0))
    assert imu.running
    imu.observe(IMU_TIME - 0.1, _odom(0.0, Pose2D(), v=0.0), None)
    assert imu.running
    imu.observe(IMU_TIME, _odom(0.0, Pose2D(), v=0.0), None)
    assert not imu.running and imu.calibrated_at == IMU_TIME and not imu.failed
    imu.start(10.0, _odom(10.0, Pose2D(), v=0.0))
    imu.observe(11.0, _odom(11.0, Pose2D(), v=0.0, w=0.5), None)
    assert not imu.running and imu.failed
