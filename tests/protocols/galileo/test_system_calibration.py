"""Calibration, software update and preview channel over real HTTP (galileo-http-a E-09–E-21,
E-51, E-52)."""

from __future__ import annotations

from polynav.geometry import Pose2D
from tests.protocols.galileo.conftest import Harness

COVERED = {
    "GET /api/v1/system/calibrate_imu": "test_imu_calibration_starts_only_standing_still",
    "GET /api/v1/system/calibrate_camera/start": "test_camera_calibration_runs_its_state_machine",
    "GET /api/v1/system/calibrate_camera/status": "test_camera_calibration_runs_its_state_machine",
    "GET /api/v1/system/calibrate_camera/complete":
        "test_camera_calibration_runs_its_state_machine",
    "GET /api/v1/system/calibrate_camera/cancel": "test_camera_calibration_can_be_cancelled",
    "GET /api/v1/system/calibrate_laser/start": "test_lidar_calibration_follows_the_camera",
    "GET /api/v1/system/calibrate_laser/status": "test_lidar_calibration_follows_the_camera",
    "GET /api/v1/system/calibrate_laser/complete": "test_lidar_calibration_follows_the_camera",
    "GET /api/v1/system/calibrate_laser/cancel": "test_lidar_calibration_follows_the_camera",
    "GET /api/v1/system/update/check": "test_no_update_is_available_and_starting_one_is_refused",
    "GET /api/v1/system/update/start": "test_no_update_is_available_and_starting_one_is_refused",
    "GET /api/v1/system/update/cancel": "test_no_update_is_available_and_starting_one_is_refused",
    "GET /api/v1/system/update/log": "test_no_update_is_available_and_starting_one_is_refused",
    "GET /api/v1/system/use_dev": "test_use_dev_keeps_the_choice",
    "PUT /api/v1/system/use_dev": "test_use_dev_keeps_the_choice",
}


def _drive_a_loop(g: Harness) -> None:
    """Teleop a circle of 0.75 m radius (4.7 m round) and a little more, as the procedure asks,
    in the open lobby of the demo site (the robot carried there first)."""
    g.runtime.simulation.teleport("floor1", Pose2D(3.7, 12.4, 0.0))
    for _ in range(70):
        g.runtime.teleop(0.3, 0.4)
        g.runtime.advance(0.25)
    g.runtime.advance(1.0)


def test_imu_calibration_starts_only_standing_still(galileo: Harness) -> None:
    assert galileo.ok("GET", "/system/calibrate_imu") == {"result": True}
    busy = galileo.ok("GET", "/system/calibrate_imu")
    assert busy["result"] is False and "already" in busy["description"]
    galileo.runtime.advance(5.5)
    galileo.runtime.teleop(0.3, 0.0)
    galileo.runtime.advance(0.3)
    moving = galileo.ok("GET", "/system/calibrate_imu")
    assert moving["result"] is False and "still" in moving["description"]


def test_camera_calibration_runs_its_state_machine(galileo: Harness) -> None:
    assert galileo.ok("GET", "/system/calibrate_camera/status") == {"status": "FREE"}
    early = galileo.get("/system/calibrate_camera/complete")
    assert early.status_code == 409 and "FREE" in early.json()["status"]
    assert galileo.ok("GET", "/system/calibrate_camera/start") == {"result": "ok"}
    assert galileo.ok("GET", "/system/calibrate_camera/status") == {"status": "CALIBRATING"}
    again = galileo.get("/system/calibrate_camera/start", camera_id=0)
    assert again.status_code == 409 and "already" in again.json()["result"]
    _drive_a_loop(galileo)
    status = galileo.ok("GET", "/system/calibrate_camera/status")
    assert status["status"] == "CALIBRATED"
    assert isinstance(status["accuracy"], float) and 50.0 <= status["accuracy"] <= 100.0
    assert galileo.ok("GET", "/system/calibrate_camera/complete") == {"status": "ok"}
    assert galileo.ok("GET", "/system/calibrate_camera/status") == {"status": "FREE"}
    bad = galileo.get("/system/calibrate_camera/start", camera_id=3)
    assert bad.status_code == 400 and "camera_id" in bad.json()["result"]


def test_camera_calibration_can_be_cancelled(galileo: Harness) -> None:
    nothing = galileo.get("/system/calibrate_camera/cancel")
    assert nothing.status_code == 409 and nothing.json()["result"]
    galileo.ok("GET", "/system/calibrate_camera/start")
    assert galileo.ok("GET", "/system/calibrate_camera/cancel") == {"result": "ok"}
    assert galileo.ok("GET", "/system/calibrate_camera/status") == {"status": "FREE"}
    galileo.runtime.start_navigation("floor1")
    navigating = galileo.get("/system/calibrate_camera/start")
    assert navigating.status_code == 409 and "navigating" in navigating.json()["result"]
    assert galileo.ok("GET", "/system/calibrate_camera/status") == {"status": "FREE"}


def test_lidar_calibration_follows_the_camera(galileo: Harness) -> None:
    first = galileo.get("/system/calibrate_laser/start")
    assert first.status_code == 409 and "camera first" in first.json()["status"]
    assert galileo.ok("GET", "/system/calibrate_laser/status") == {"status": "FREE"}
    galileo.ok("GET", "/system/calibrate_camera/start")
    _drive_a_loop(galileo)
    galileo.ok("GET", "/system/calibrate_camera/complete")
    assert galileo.ok("GET", "/system/calibrate_laser/start") == {"status": "ok"}
    assert galileo.ok("GET", "/system/calibrate_laser/cancel") == {"status": "ok"}
    assert galileo.get("/system/calibrate_laser/cancel").status_code == 409
    assert galileo.ok("GET", "/system/calibrate_laser/start") == {"status": "ok"}
    assert galileo.ok("GET", "/system/calibrate_laser/status")["status"] == "CALIBRATING"
    assert galileo.get("/system/calibrate_laser/complete").status_code == 409
    _drive_a_loop(galileo)  # 5 m and more than half a turn with the walls in view
    status = galileo.ok("GET", "/system/calibrate_laser/status")
    assert status["status"] == "CALIBRATED" and status["accuracy"] > 50.0
    assert galileo.ok("GET", "/system/calibrate_laser/complete") == {"status": "ok"}
    assert galileo.ok("GET", "/system/calibrate_laser/status") == {"status": "FREE"}


def test_no_update_is_available_and_starting_one_is_refused(galileo: Harness) -> None:
    assert galileo.ok("GET", "/system/update/check") == {"status": "ok", "need_update": False}
    start = galileo.get("/system/update/start")
    assert start.status_code == 409 and "no update available" in start.json()["status"]
    assert galileo.get("/system/update/cancel").status_code == 409
    log = galileo.ok("GET", "/system/update/log")
    assert log["status"] == "ok" and log["is_complete"] is True
    assert "no update available" in log["log"]


def test_use_dev_keeps_the_choice(galileo: Harness) -> None:
    assert galileo.ok("GET", "/system/use_dev") == {"use_dev": False}
    assert galileo.ok("PUT", "/system/use_dev", json={"use_dev": True}) == {"use_dev": True}
    assert galileo.ok("GET", "/system/use_dev") == {"use_dev": True}
    assert galileo.put("/system/use_dev", {"use_dev": "maybe"}).status_code == 400
    assert galileo.ok("GET", "/system/use_dev") == {"use_dev": True}
