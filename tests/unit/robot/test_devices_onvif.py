from __future__ import annotations

import pytest

from polynav.errors import InvalidRequest
from polynav.robot.devices import PtzPose
from polynav.robot.sim.devices.onvif import PAN_SPEED, PRESETS, SimPtzCamera


def test_an_absolute_move_runs_at_its_speed_on_the_clock() -> None:
    cam = SimPtzCamera(lambda: None)
    cam.move_to(0.0, PtzPose(0.5, -0.25, 1.0))
    assert cam.pose(0.5) == PtzPose(0.5 * PAN_SPEED, -0.25, 0.5 * PAN_SPEED)
    assert cam.pose(2.0) == PtzPose(0.5, -0.25, 1.0)


def test_a_speed_move_runs_until_stopped_or_the_limit() -> None:
    cam = SimPtzCamera(lambda: None)
    cam.move_speed(0.0, 0.2, 0.0, 0.0)
    assert cam.pose(1.0).pan == pytest.approx(0.2)
    cam.move_speed(1.0, 0.0, 0.0, 0.0)
    assert cam.pose(5.0).pan == pytest.approx(0.2)
    cam.move_speed(5.0, 0.0, -1.0, 0.0)
    assert cam.pose(10.0).tilt == -1.0


def test_presets_and_bad_values() -> None:
    cam = SimPtzCamera(lambda: None)
    cam.goto_preset(0.0, "back")
    assert cam.pose(10.0) == PRESETS["back"]
    with pytest.raises(InvalidRequest):
        cam.goto_preset(10.0, "nowhere")
    for pose in (PtzPose(1.5, 0.0, 0.0), PtzPose(0.0, 0.0, -0.1), PtzPose(float("nan"), 0, 0)):
        with pytest.raises(InvalidRequest):
            cam.move_to(10.0, pose)
    with pytest.raises(InvalidRequest):
        cam.move_speed(10.0, 2.0, 0.0, 0.0)
    assert cam.pose(20.0) == PRESETS["back"]


def test_login_needs_the_camera_address_and_its_credentials() -> None:
    cam = SimPtzCamera(lambda: None)
    ip, port = cam.address
    cam.check_login(ip, port, "admin", "polynav")
    cam.check_login("", 0, "admin", "polynav")  # empty ip: the first camera found
    with pytest.raises(InvalidRequest, match="no ONVIF camera"):
        cam.check_login("192.0.2.99", port, "admin", "polynav")
    with pytest.raises(InvalidRequest, match="refused"):
        cam.check_login(ip, port, "admin", "wrong")


def test_a_snapshot_is_a_jpeg() -> None:
    assert SimPtzCamera(lambda: None).snapshot(0.0)[:2] == b"\xff\xd8"
