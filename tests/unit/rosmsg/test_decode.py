"""ROS messages read back into polynav's values: what the encoders write reads back the same,
and a bad message is a ValueError that names the field."""

from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.geometry import Pose2D, Twist
from polynav.robot.interface import BatteryState, ImuReading, LaserScan, Odometry
from polynav.rosmsg import decode, encode


def test_twist_reads_linear_x_and_angular_z() -> None:
    assert decode.twist(encode.twist(Twist(0.3, -0.5))) == Twist(0.3, -0.5)
    assert decode.twist({"linear": {"x": 1}}) == Twist(1.0, 0.0)  # absent fields are 0
    assert decode.twist({}) == Twist(0.0, 0.0)


@pytest.mark.parametrize(("message", "text"), [
    ("fast", "Twist: must be an object"),
    ([0.1, 0.2], "Twist: must be an object"),
    ({"linear": 3}, "'linear' and 'angular' must be objects"),
    ({"angular": [1]}, "'linear' and 'angular' must be objects"),
    ({"linear": {"x": "fast"}}, "Twist.linear.x: must be a finite number, got 'fast'"),
    ({"linear": {"x": True}}, "Twist.linear.x: must be a finite number"),
    ({"angular": {"z": math.nan}}, "Twist.angular.z: must be a finite number"),
    ({"angular": {"z": math.inf}}, "Twist.angular.z: must be a finite number"),
    ({"angular": {"z": None}}, "Twist.angular.z: missing"),
])
def test_a_bad_twist_names_the_field(message: object, text: str) -> None:
    with pytest.raises(ValueError) as caught:
        decode.twist(message)
    assert text in str(caught.value)


def test_pose_stamp_and_odometry_read_back() -> None:
    p = Pose2D(1.5, -0.25, 2.5)
    back = decode.pose(encode.pose(p))
    assert back.distance_to(p) < 1e-12 and math.isclose(back.theta, p.theta)
    assert decode.stamp(encode.header(0, 12.345, "map")) == pytest.approx(12.345)
    assert decode.stamp({"secs": 3, "nsecs": 5}) == pytest.approx(3.000000005)
    reading = Odometry(2.0, p, Twist(0.4, 0.1))
    odom = decode.odometry(encode.odometry(1, reading), 2.0)
    assert odom.pose.distance_to(p) < 1e-12 and odom.twist == Twist(0.4, 0.1)
    with pytest.raises(ValueError, match="Odometry.pose"):
        decode.odometry({"pose": {"pose": 1}, "twist": {"twist": {}}}, 0.0)
    with pytest.raises(ValueError, match="position.x: missing"):
        decode.pose({"position": {"y": 1.0}, "orientation": {}})


def test_imu_battery_and_scan_read_back() -> None:
    imu = decode.imu(encode.imu(0, ImuReading(1.0, -2.0, 0.3, 0.4)), 1.0)
    assert imu.yaw == pytest.approx(-2.0) and imu.angular_velocity == 0.3
    assert imu.linear_acceleration == 0.4
    battery = decode.battery_state(
        encode.battery_state(0, BatteryState(1.0, 64.0, 24.5, -2.0, charging=True)), 1.0)
    assert battery.percent == pytest.approx(64.0) and battery.charging
    ranges = np.array([1.5, np.inf, 3.0], dtype=np.float32)
    scan = LaserScan(5.0, -0.5, 0.5, 0.05, 8.0, ranges)
    back = decode.laser_scan(encode.laser_scan(0, scan), 5.0, Pose2D())
    assert back.ranges[0] == pytest.approx(1.5) and math.isinf(back.ranges[1])
    assert back.angle_increment == 0.5
    with pytest.raises(ValueError, match="angle_increment: must not be 0"):
        decode.laser_scan({"angle_min": 0, "angle_increment": 0, "range_max": 5,
                           "ranges": [1.0]}, 0.0, Pose2D())
    with pytest.raises(ValueError, match="ranges: must be a non-empty array"):
        decode.laser_scan({"angle_min": 0, "angle_increment": 0.1, "range_max": 5,
                           "ranges": "far"}, 0.0, Pose2D())
