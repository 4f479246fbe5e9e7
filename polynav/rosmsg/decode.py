"""ROS messages read into polynav's values, checked field by field.

Every reader raises :class:`ValueError` with a text naming the field, so a wire answers a bad
message with its own error and a robot driver drops it with a log line.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from polynav.geometry import Pose2D, Twist
from polynav.robot.interface import BatteryState, ImuReading, LaserScan, Odometry


def number(message: Mapping[str, Any], key: str, where: str, default: float | None = None
           ) -> float:
    """A finite number field (``default`` when absent, if given)."""
    value = message.get(key, default)
    if value is None:
        raise ValueError(f"{where}.{key}: missing")
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(
            value):
        raise ValueError(f"{where}.{key}: must be a finite number, got {value!r}")
    return float(value)


def mapping(message: Mapping[str, Any], key: str, where: str) -> Mapping[str, Any]:
    value = message.get(key)
    if not isinstance(value, Mapping):
        raise ValueError(f"{where}.{key}: must be an object")
    return value


def twist(message: Any, where: str = "Twist") -> Twist:
    """``geometry_msgs/Twist``: ``linear.x`` [m/s] and ``angular.z`` [rad/s] (absent: 0)."""
    if not isinstance(message, Mapping):
        raise ValueError(f"{where}: must be an object")
    linear = message.get("linear", {})
    angular = message.get("angular", {})
    if not isinstance(linear, Mapping) or not isinstance(angular, Mapping):
        raise ValueError(f"{where}: 'linear' and 'angular' must be objects")
    return Twist(number(linear, "x", f"{where}.linear", 0.0),
                 number(angular, "z", f"{where}.angular", 0.0))


def yaw(quaternion: Mapping[str, Any], where: str = "orientation") -> float:
    """The yaw of a quaternion [rad]."""
    x, y, z, w = (number(quaternion, k, where, 0.0 if k != "w" else 1.0) for k in "xyzw")
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def pose(message: Mapping[str, Any], where: str = "pose") -> Pose2D:
    """``geometry_msgs/Pose`` as a planar pose."""
    position = mapping(message, "position", where)
    orientation = mapping(message, "orientation", where)
    return Pose2D(number(position, "x", f"{where}.position"),
                  number(position, "y", f"{where}.position"),
                  yaw(orientation, f"{where}.orientation"))


def stamp(message: Mapping[str, Any], where: str = "header") -> float:
    """A header's ``stamp`` (or a bare ``time``) in seconds."""
    value = message.get("stamp", message)
    if not isinstance(value, Mapping):
        raise ValueError(f"{where}.stamp: must be an object")
    return number(value, "secs", f"{where}.stamp") + number(value, "nsecs", f"{where}.stamp",
                                                             0.0) * 1e-9


def odometry(message: Mapping[str, Any], stamp: float) -> Odometry:
    """``nav_msgs/Odometry`` stamped ``stamp`` (the caller's clock)."""
    pose_part = mapping(mapping(message, "pose", "Odometry"), "pose", "Odometry.pose")
    twist_part = mapping(mapping(message, "twist", "Odometry"), "twist", "Odometry.twist")
    return Odometry(stamp, pose(pose_part, "Odometry.pose.pose"),
                    twist(twist_part, "Odometry.twist.twist"))


def laser_scan(message: Mapping[str, Any], stamp: float, sensor_pose: Pose2D) -> LaserScan:
    """``sensor_msgs/LaserScan``: a beam with no return (null, NaN, beyond ``range_max``, below
    ``range_min``) is ``inf``."""
    angle_min = number(message, "angle_min", "LaserScan")
    increment = number(message, "angle_increment", "LaserScan")
    range_min = number(message, "range_min", "LaserScan", 0.0)
    range_max = number(message, "range_max", "LaserScan")
    raw = message.get("ranges")
    if not isinstance(raw, list) or not raw:
        raise ValueError("LaserScan.ranges: must be a non-empty array")
    if increment == 0.0:
        raise ValueError("LaserScan.angle_increment: must not be 0")
    values = [r if isinstance(r, (int, float)) and not isinstance(r, bool) else math.nan
              for r in raw]
    ranges = np.asarray(values, dtype=np.float64)
    bad = ~np.isfinite(ranges) | (ranges > range_max) | (ranges < range_min)
    ranges[bad] = np.inf
    return LaserScan(stamp, angle_min, increment, range_min, range_max,
                     ranges.astype(np.float32), sensor_pose)


def imu(message: Mapping[str, Any], stamp: float) -> ImuReading:
    """``sensor_msgs/Imu``: yaw, yaw rate and forward acceleration."""
    return ImuReading(
        stamp,
        yaw(mapping(message, "orientation", "Imu"), "Imu.orientation"),
        number(mapping(message, "angular_velocity", "Imu"), "z", "Imu.angular_velocity", 0.0),
        number(mapping(message, "linear_acceleration", "Imu"), "x",
               "Imu.linear_acceleration", 0.0),
    )


def battery_state(message: Mapping[str, Any], stamp: float) -> BatteryState:
    """``sensor_msgs/BatteryState`` (``percentage`` 0..1; a driver that writes 0..100 is read
    as per cent too)."""
    share = number(message, "percentage", "BatteryState")
    percent = share * 100.0 if share <= 1.0 else share
    voltage = message.get("voltage")
    current = message.get("current")
    status = message.get("power_supply_status")
    return BatteryState(
        stamp, max(0.0, min(100.0, percent)),
        float(voltage) if isinstance(voltage, (int, float)) and math.isfinite(voltage) else 0.0,
        float(current) if isinstance(current, (int, float)) and math.isfinite(current) else 0.0,
        status in (1, 4),  # CHARGING or FULL (on the charger)
    )
