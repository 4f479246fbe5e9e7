"""``/api/robot/...`` (issue 33 item 2): status with the state and error tables of
docs/puwei.md, clear, pause/resume and charging on the runtime's docking."""

from __future__ import annotations

import pytest

from polynav.geometry import Pose2D, quaternion_to_yaw
from tests.protocols.puwei.conftest import Harness, refused

COVERED = {
    "GET /api/robot/status": "test_status_has_the_o_status_fields",
    "GET /api/robot/clear": "test_clear_releases_the_software_estop_and_acknowledges_a_failure",
    "GET /api/robot/pause": "test_pause_and_resume_a_running_task",
    "GET /api/robot/charge": "test_charge_docks_onto_the_maps_charger",
}


def test_status_has_the_o_status_fields(puwei: Harness) -> None:
    data = puwei.ok("/api/robot/status")
    assert set(data) >= {"current", "percentage", "pose", "twist", "voltage", "state", "err",
                         "msg", "time_stamp", "chassis_mode"}
    snap = puwei.runtime.status()
    assert data["state"] == 0 and data["msg"] == "空闲" and data["err"] == []
    assert data["percentage"] == round(snap.battery_percent)
    position, q = data["pose"]["position"], data["pose"]["orientation"]
    assert position["x"] == pytest.approx(snap.pose.x)
    assert position["y"] == pytest.approx(snap.pose.y)
    assert quaternion_to_yaw(q["x"], q["y"], q["z"], q["w"]) == pytest.approx(snap.pose.theta)
    assert data["voltage"] > 0
    assert data["chassis_mode"] == 1
    # time_stamp: the robot's calendar in epoch milliseconds (64-bit, A20).
    assert data["time_stamp"] > 2**32
    puwei.ok("/api/roslaunch/mapping")
    assert puwei.ok("/api/robot/status")["state"] == 4


def test_clear_releases_the_software_estop_and_acknowledges_a_failure(puwei: Harness) -> None:
    puwei.runtime.set_software_estop(True)
    puwei.runtime.advance(0.1)
    data = puwei.ok("/api/robot/status")
    assert "1-2" in data["err"] and data["state"] == 6 and data["chassis_mode"] == 2
    assert puwei.ok("/api/robot/clear") == []
    puwei.runtime.advance(0.1)
    assert puwei.ok("/api/robot/status")["err"] == []
    # A goal off the map fails ("no path": 4-1) and is reported until cleared.
    puwei.navigate()
    puwei.runtime.go_to(pose=Pose2D(1000.0, 1000.0, 0.0))
    puwei.runtime.advance(2.0)
    assert "4-1" in puwei.ok("/api/robot/status")["err"]
    assert "4-1" not in puwei.ok("/api/robot/clear")
    assert puwei.ok("/api/robot/status")["err"] == []


def test_pause_and_resume_a_running_task(puwei: Harness) -> None:
    assert refused(puwei.get("/api/robot/pause"))["code"] == 4  # nothing runs
    puwei.navigate()
    body = {"name": "round", "mode": 0, "loop": 1, "minute": None, "hour": None, "opt": None,
            "actions": [{"type": 5, "value": ["kitchen", "lobby"]}]}
    assert puwei.post("/api/task/set", body).json()["code"] == 0
    puwei.runtime.advance(1.0)
    assert puwei.ok("/api/robot/status")["state"] == 1
    assert puwei.ok("/api/robot/pause", value="true") is None
    puwei.runtime.advance(0.5)
    assert puwei.runtime.tasks.running()["state"] == "PAUSED"
    assert puwei.ok("/api/robot/status")["state"] == 2
    assert puwei.ok("/api/robot/pause", value="false") is None
    puwei.runtime.advance(0.5)
    assert puwei.runtime.tasks.running()["state"] == "WORKING"
    assert refused(puwei.get("/api/robot/pause", value="maybe"))["code"] == 2


def test_charge_docks_onto_the_maps_charger(puwei: Harness) -> None:
    assert refused(puwei.get("/api/robot/charge"))["code"] == 4  # not navigating
    puwei.navigate()
    assert refused(puwei.get("/api/robot/charge", value="false"))["code"] == 4
    assert puwei.ok("/api/robot/charge", value="true") is None
    task = puwei.runtime.tasks.running()
    assert task is not None and task["kind"] == "puwei_charge"
    assert puwei.advance_until(lambda: puwei.runtime.status().charging, 180.0, step=1.0)
    assert puwei.ok("/api/robot/status")["state"] == 3


def test_charge_false_cancels_docking(puwei: Harness) -> None:
    puwei.navigate()
    puwei.ok("/api/robot/charge")
    puwei.runtime.advance(0.5)
    assert puwei.ok("/api/robot/charge", value="false") is None
    puwei.runtime.advance(0.2)
    assert puwei.runtime.tasks.running() is None
