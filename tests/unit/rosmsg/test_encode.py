"""polynav's values written as ROS 1 messages: field names, nesting and the ``.msg`` key
order, stamps, covariances, and the occupancy grid's cell order (ROS: row-major from the
bottom-left cell)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from polynav.geometry import Pose2D, Twist
from polynav.maps.map import Map, MapInfo
from polynav.robot.interface import BatteryState, ImuReading, LaserScan, Odometry
from polynav.rosmsg import encode


def test_stamp_splits_seconds_and_never_reaches_a_whole_second_of_nanoseconds() -> None:
    assert encode.stamp(12.25) == {"secs": 12, "nsecs": 250_000_000}
    assert list(encode.stamp(1.5)) == ["secs", "nsecs"]
    assert encode.stamp(3.9999999999) == {"secs": 3, "nsecs": 999_999_999}
    assert encode.stamp(-2.0) == {"secs": 0, "nsecs": 0}
    assert encode.stamp(1_736_124_716.247740752)["secs"] == 1_736_124_716


def test_header_and_pose_stamped_in_msg_order() -> None:
    msg = encode.pose_stamped(5, 2.5, "map", Pose2D(1.0, -2.0, math.pi / 2))
    assert list(msg) == ["header", "pose"]
    assert list(msg["header"]) == ["seq", "stamp", "frame_id"]
    assert msg["header"] == {"seq": 5, "stamp": {"secs": 2, "nsecs": 500_000_000},
                             "frame_id": "map"}
    pose = msg["pose"]
    assert list(pose) == ["position", "orientation"]
    assert pose["position"] == {"x": 1.0, "y": -2.0, "z": 0.0}
    q = pose["orientation"]
    assert list(q) == ["x", "y", "z", "w"]
    assert q["z"] == pytest.approx(math.sqrt(0.5)) and q["w"] == pytest.approx(math.sqrt(0.5))
    assert q["x"] == 0.0 and q["y"] == 0.0


def test_twist_and_vector3() -> None:
    msg = encode.twist(Twist(0.4, -0.2))
    assert msg == {"linear": {"x": 0.4, "y": 0.0, "z": 0.0},
                   "angular": {"x": 0.0, "y": 0.0, "z": -0.2}}
    assert list(msg) == ["linear", "angular"]
    assert list(encode.point(1, 2, 3)) == ["x", "y", "z"]


def test_odometry_fields_covariances_and_pose_override() -> None:
    reading = Odometry(7.0, Pose2D(1.0, 2.0, 0.3), Twist(0.5, 0.1))
    msg = encode.odometry(3, reading)
    assert list(msg) == ["header", "child_frame_id", "pose", "twist"]
    assert msg["header"]["frame_id"] == "odom" and msg["child_frame_id"] == "base_link"
    assert list(msg["pose"]) == ["pose", "covariance"]
    assert list(msg["twist"]) == ["twist", "covariance"]
    assert msg["pose"]["covariance"] == [0.0] * 36
    assert msg["twist"]["twist"]["linear"]["x"] == 0.5
    assert msg["twist"]["twist"]["angular"]["z"] == 0.1
    cov = [0.01 * i for i in range(36)]
    carried = encode.odometry(4, reading, "odom", "base_footprint", Pose2D(9.0, 8.0),
                              pose_covariance=cov)
    assert carried["pose"]["pose"]["position"]["x"] == 9.0
    assert carried["child_frame_id"] == "base_footprint"
    assert carried["pose"]["covariance"] == pytest.approx(cov)
    with pytest.raises(ValueError, match="36 values"):
        encode.odometry(5, reading, twist_covariance=[0.0] * 9)


def test_imu_in_msg_order_with_yaw_override() -> None:
    reading = ImuReading(1.0, 0.5, 0.2, -0.3)
    msg = encode.imu(0, reading)
    assert list(msg) == ["header", "orientation", "orientation_covariance", "angular_velocity",
                         "angular_velocity_covariance", "linear_acceleration",
                         "linear_acceleration_covariance"]
    assert msg["header"]["frame_id"] == "imu_link"
    assert msg["angular_velocity"] == {"x": 0.0, "y": 0.0, "z": 0.2}
    assert msg["linear_acceleration"] == {"x": -0.3, "y": 0.0, "z": 0.0}
    assert all(len(msg[k]) == 9 for k in msg if k.endswith("covariance"))
    assert msg["orientation"]["z"] == pytest.approx(math.sin(0.25))
    turned = encode.imu(1, reading, yaw=1.0, orientation_covariance=[1e-3] + [0.0] * 8)
    assert turned["orientation"]["z"] == pytest.approx(math.sin(0.5))
    assert turned["orientation_covariance"][0] == 1e-3


def test_laser_scan_no_return_is_above_range_max_and_json_has_no_infinity() -> None:
    ranges = np.array([1.0, np.inf, 2.123456, np.nan], dtype=np.float32)
    scan = LaserScan(4.0, -1.0, 0.5, 0.1, 10.0, ranges, Pose2D(0.2, 0.0))
    msg = encode.laser_scan(9, scan, scan_time=0.0667)
    assert list(msg) == ["header", "angle_min", "angle_max", "angle_increment",
                         "time_increment", "scan_time", "range_min", "range_max", "ranges",
                         "intensities"]
    assert msg["header"]["frame_id"] == "laser"
    assert msg["angle_max"] == pytest.approx(0.5)
    assert msg["ranges"][0] == pytest.approx(1.0)
    assert msg["ranges"][1] > msg["range_max"] and msg["ranges"][3] > msg["range_max"]
    assert msg["ranges"][2] == pytest.approx(2.1235, abs=1e-6)
    assert all(isinstance(r, float) for r in msg["ranges"])
    json.dumps(msg, allow_nan=False)


def test_occupancy_grid_is_row_major_from_the_bottom_left_cell() -> None:
    # 4 x 3 cells of 0.5 m from (-1, 2): one wall cell in the top-left corner (the row of
    # the largest y), one unknown cell in the bottom-right corner, the rest free.
    data = np.zeros((3, 4), dtype=np.int8)
    data[2, 0] = 100
    data[0, 3] = -1
    grid = Map(MapInfo(0.5, 4, 3, Pose2D(-1.0, 2.0)), data)
    msg = encode.occupancy_grid(2, 10.0, grid)
    assert list(msg) == ["header", "info", "data"]
    info = msg["info"]
    assert list(info) == ["map_load_time", "resolution", "width", "height", "origin"]
    assert (info["width"], info["height"], info["resolution"]) == (4, 3, 0.5)
    assert info["origin"]["position"] == {"x": -1.0, "y": 2.0, "z": 0.0}
    cells = msg["data"]
    assert len(cells) == 12 and all(isinstance(c, int) for c in cells)

    def ros_cell(x: float, y: float) -> int:  # the ROS formula, not polynav's
        col = math.floor((x - info["origin"]["position"]["x"]) / info["resolution"])
        row = math.floor((y - info["origin"]["position"]["y"]) / info["resolution"])
        return int(cells[col + row * info["width"]])

    assert ros_cell(-0.75, 3.25) == 100  # top-left: x smallest, y largest
    assert ros_cell(0.75, 2.25) == -1  # bottom-right
    assert ros_cell(-0.75, 2.25) == 0  # bottom-left, the first cell
    assert cells.count(100) == 1 and cells.count(-1) == 1
    assert not grid.is_free_at(-0.75, 3.25)  # polynav reads the same cell as the wall


def test_battery_state_percentage_is_a_share() -> None:
    msg = encode.battery_state(0, BatteryState(1.0, 80.0, 25.2, -1.5, charging=True))
    assert msg["percentage"] == pytest.approx(0.8)
    assert msg["power_supply_status"] == 1  # CHARGING
    assert list(msg)[:2] == ["header", "voltage"] and list(msg)[-1] == "serial_number"
    assert encode.battery_state(0, BatteryState(1.0, 5.0, 24.0, -1.0, charging=False))[
        "power_supply_status"] == 2  # DISCHARGING


def test_tf_clock_and_small_messages() -> None:
    t = encode.transform_stamped(1, 2.0, "odom", "base_link", Pose2D(1.0, 0.5, -0.4))
    assert list(t) == ["header", "child_frame_id", "transform"]
    assert list(t["transform"]) == ["translation", "rotation"]
    assert list(t["transform"]["rotation"]) == ["x", "y", "z", "w"]
    assert encode.tf_message([t]) == {"transforms": [t]}
    assert encode.clock(3.5) == {"clock": {"secs": 3, "nsecs": 500_000_000}}
    assert encode.int16(-7) == {"data": -7}
    assert encode.string("ok") == {"data": "ok"}
    assert encode.trigger_response(True, "done") == {"success": True, "message": "done"}
    assert list(encode.trigger_response(False)) == ["success", "message"]
