"""ROS messages read into polynav's values, checked field by field.

Every reader raises :class:`ValueError` with a text naming the field, so a wire answers a bad
message with its own error and a robot driver drops it with a log line.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from polynav.geometry import Pose2D, Twist


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
