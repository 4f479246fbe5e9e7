"""Black-box accuracy, the way Yunji integrators check a robot.

One socket subscribes to ``robot_status`` at 2 Hz; for every marker of floor 1 a fresh socket
sends ``/api/move?marker=...``; the integrator waits while ``move_status`` is ``running`` (reading
the 2 Hz callbacks) and then compares the reported pose with the marker's pose from
``/api/markers/query_list``. Simulated time stands in for the integrator's wall clock: the test
advances it half a second per callback.
"""

from __future__ import annotations

import math
from typing import Any

from polynav.geometry import angle_diff, quaternion_to_yaw
from tests.protocols.yunji.conftest import Harness

POSITION_TOLERANCE = 0.05  # [m]
HEADING_TOLERANCE = 0.1  # [rad]
MOVE_TIMEOUT = 240.0  # simulated seconds per marker
PERIOD = 0.5  # 2 Hz


def _marker_pose(marker: dict[str, Any]) -> tuple[float, float, float]:
    position, orientation = marker["pose"]["position"], marker["pose"]["orientation"]
    yaw = quaternion_to_yaw(orientation["x"], orientation["y"], orientation["z"], orientation["w"])
    return position["x"], position["y"], yaw


def test_every_marker_of_floor_1_is_reached_within_5_cm_and_0_1_rad(harness: Harness) -> None:
    watcher = harness.client()
    markers = watcher.request("/api/markers/query_list?floor=1")["results"]
    assert len(markers) >= 10
    subscribed = watcher.request("/api/request_data?topic=robot_status&frequency=2")
    assert subscribed["status"] == "OK"
    report: dict[str, tuple[float, float]] = {}
    for name, marker in markers.items():
        mover = harness.client()
        reply = mover.request(f"/api/move?marker={name}")
        assert reply["status"] == "OK", (name, reply)
        mover.close()
        harness.clients.remove(mover)
        status: dict[str, Any] = {}
        for _ in range(int(MOVE_TIMEOUT / PERIOD)):
            harness.runtime.advance(PERIOD)
            status = watcher.push("callback", "robot_status")["results"]
            # A callback sent before the move shows the previous task: wait for this one.
            if status["move_target"] == name and status["move_status"] != "running":
                break
        assert status["move_status"] == "succeeded", (name, status)
        x, y, yaw = _marker_pose(marker)
        pose = status["current_pose"]
        report[name] = (math.hypot(pose["x"] - x, pose["y"] - y),
                        abs(angle_diff(pose["theta"], yaw)))
        true = harness.runtime.simulation.true_pose
        assert math.hypot(true.x - x, true.y - y) < 2 * POSITION_TOLERANCE, (name, true)
    misses = {name: err for name, err in report.items()
              if err[0] > POSITION_TOLERANCE or err[1] > HEADING_TOLERANCE}
    assert misses == {}, report
    assert harness.runtime.simulation.collisions == []
