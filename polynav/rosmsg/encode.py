"""polynav's values as ROS messages (dicts in the ``.msg`` field order).

Stamps are the runtime's clock [s] as ``{secs, nsecs}``. A lidar beam with no return (``inf``)
is written as ``range_max + 1``: above ``range_max``, which ROS consumers read as "no return",
where JSON has no infinity.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from polynav.geometry import Pose2D, Twist, yaw_to_quaternion
from polynav.maps.map import Map
from polynav.robot.interface import BatteryState, ImuReading, LaserScan, Odometry

Message = dict[str, Any]

#: Covariance of a quantity not measured (ROS: -1 in the first element means "no estimate").
UNKNOWN_COVARIANCE = (-1.0,) + (0.0,) * 8


def time(seconds: float) -> dict[str, int]:
    """A ROS ``time``: whole seconds and nanoseconds (never negative)."""
    seconds = max(0.0, seconds)
    secs = int(seconds)
    return {"secs": secs, "nsecs": min(999_999_999, int(round((seconds - secs) * 1e9)))}


#: A header's stamp is a ROS ``time`` of the runtime's clock: ``stamp(t)`` -> ``{secs, nsecs}``.
stamp = time


def header(seq: int, stamp: float, frame_id: str) -> Message:
    """``std_msgs/Header``."""
    return {"seq": seq, "stamp": time(stamp), "frame_id": frame_id}


def vector3(x: float = 0.0, y: float = 0.0, z: float = 0.0) -> Message:
    """``geometry_msgs/Vector3``."""
    return {"x": float(x), "y": float(y), "z": float(z)}


def point(x: float = 0.0, y: float = 0.0, z: float = 0.0) -> Message:
    """``geometry_msgs/Point`` (the same fields as a Vector3; a position, not a direction)."""
    return vector3(x, y, z)


def quaternion(yaw: float) -> Message:
    """``geometry_msgs/Quaternion`` of a rotation by ``yaw`` [rad] about +z."""
    x, y, z, w = yaw_to_quaternion(yaw)
    return {"x": x, "y": y, "z": z, "w": w}


def pose(p: Pose2D) -> Message:
    """``geometry_msgs/Pose`` of a planar pose."""
    return {"position": point(p.x, p.y), "orientation": quaternion(p.theta)}


def pose_stamped(seq: int, stamp: float, frame_id: str, p: Pose2D) -> Message:
    """``geometry_msgs/PoseStamped``."""
    return {"header": header(seq, stamp, frame_id), "pose": pose(p)}


def twist(t: Twist) -> Message:
    """``geometry_msgs/Twist`` of a planar body velocity."""
    return {"linear": vector3(t.linear), "angular": vector3(z=t.angular)}


def covariance(values: Sequence[float] | None, size: int) -> list[float]:
    """A row-major ``size`` x ``size`` covariance (zeros when not given: ROS's "unknown").

    Raises:
        ValueError: ``values`` has not ``size * size`` elements.
    """
    if values is None:
        return [0.0] * (size * size)
    if len(values) != size * size:
        raise ValueError(f"a {size}x{size} covariance has {size * size} values, "
                         f"got {len(values)}")
    return [float(v) for v in values]


def odometry(seq: int, reading: Odometry, frame_id: str = "odom",
             child_frame_id: str = "base_link", pose_override: Pose2D | None = None,
             pose_covariance: Sequence[float] | None = None,
             twist_covariance: Sequence[float] | None = None) -> Message:
    """``nav_msgs/Odometry``: the pose (``pose_override`` instead of the reading's, for a
    pose carried to the stamp) and the body velocity, each with its 6x6 covariance."""
    return {
        "header": header(seq, reading.stamp, frame_id),
        "child_frame_id": child_frame_id,
        "pose": {"pose": pose(pose_override or reading.pose),
                 "covariance": covariance(pose_covariance, 6)},
        "twist": {"twist": twist(reading.twist), "covariance": covariance(twist_covariance, 6)},
    }


def laser_scan(seq: int, scan: LaserScan, frame_id: str = "laser",
               scan_time: float = 0.0) -> Message:
    """``sensor_msgs/LaserScan`` (see the module docstring for beams with no return)."""
    n = len(scan.ranges)
    ranges = np.asarray(scan.ranges, dtype=np.float64)
    ranges = np.where(np.isfinite(ranges), ranges, scan.range_max + 1.0)
    return {
        "header": header(seq, scan.stamp, frame_id),
        "angle_min": float(scan.angle_min),
        "angle_max": float(scan.angle_min + scan.angle_increment * max(0, n - 1)),
        "angle_increment": float(scan.angle_increment),
        "time_increment": 0.0,
        "scan_time": float(scan_time),
        "range_min": float(scan.range_min),
        "range_max": float(scan.range_max),
        "ranges": [round(float(r), 4) for r in ranges],
        "intensities": [],
    }


def imu(seq: int, reading: ImuReading, frame_id: str = "imu_link",
        yaw: float | None = None, orientation_covariance: Sequence[float] | None = None,
        angular_velocity_covariance: Sequence[float] | None = None,
        linear_acceleration_covariance: Sequence[float] | None = None) -> Message:
    """``sensor_msgs/Imu`` of a planar IMU: orientation from the integrated yaw (``yaw``
    instead, for a yaw carried to the stamp), yaw rate, forward acceleration, each with its
    3x3 covariance."""
    return {
        "header": header(seq, reading.stamp, frame_id),
        "orientation": quaternion(reading.yaw if yaw is None else yaw),
        "orientation_covariance": covariance(orientation_covariance, 3),
        "angular_velocity": vector3(z=reading.angular_velocity),
        "angular_velocity_covariance": covariance(angular_velocity_covariance, 3),
        "linear_acceleration": vector3(reading.linear_acceleration),
        "linear_acceleration_covariance": covariance(linear_acceleration_covariance, 3),
    }


# sensor_msgs/BatteryState power_supply_status and _technology values.
_CHARGING, _DISCHARGING = 1, 2
_LION = 2


def battery_state(seq: int, battery: BatteryState, frame_id: str = "base_link") -> Message:
    """``sensor_msgs/BatteryState`` (``percentage`` 0..1, as ROS)."""
    return {
        "header": header(seq, battery.stamp, frame_id),
        "voltage": float(battery.voltage),
        "temperature": math.nan,
        "current": float(battery.current),
        "charge": math.nan,
        "capacity": math.nan,
        "design_capacity": math.nan,
        "percentage": float(battery.percent) / 100.0,
        "power_supply_status": _CHARGING if battery.charging else _DISCHARGING,
        "power_supply_health": 0,
        "power_supply_technology": _LION,
        "present": True,
        "cell_voltage": [],
        "cell_temperature": [],
        "location": "",
        "serial_number": "",
    }


def transform_stamped(seq: int, stamp: float, frame_id: str, child_frame_id: str,
                      p: Pose2D) -> Message:
    """``geometry_msgs/TransformStamped``: ``child_frame_id``'s pose in ``frame_id``."""
    return {
        "header": header(seq, stamp, frame_id),
        "child_frame_id": child_frame_id,
        "transform": {"translation": vector3(p.x, p.y), "rotation": quaternion(p.theta)},
    }


def tf_message(transforms: Sequence[Message]) -> Message:
    """``tf2_msgs/TFMessage``."""
    return {"transforms": list(transforms)}


def clock(stamp: float) -> Message:
    """``rosgraph_msgs/Clock``."""
    return {"clock": time(stamp)}


def occupancy_grid(seq: int, stamp: float, grid: Map, frame_id: str = "map") -> Message:
    """``nav_msgs/OccupancyGrid``: row-major from the bottom-left cell, -1 unknown, 0 free,
    100 occupied (polynav's grids are stored the same way)."""
    info = grid.info
    return {
        "header": header(seq, stamp, frame_id),
        "info": {
            "map_load_time": time(stamp),
            "resolution": float(info.resolution),
            "width": int(info.width),
            "height": int(info.height),
            "origin": pose(info.origin),
        },
        "data": np.asarray(grid.data, dtype=np.int8).reshape(-1).tolist(),
    }


def int16(value: int) -> Message:
    """``std_msgs/Int16``."""
    return {"data": int(value)}


def string(value: str) -> Message:
    """``std_msgs/String``."""
    return {"data": value}


def trigger_response(success: bool, message: str = "") -> Message:
    """The response of ``std_srvs/Trigger``."""
    return {"success": bool(success), "message": message}
