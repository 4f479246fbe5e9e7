"""Slide table and jacking mechanism over real HTTP (galileo-http-a E-64–E-69)."""

from __future__ import annotations

import math

import pytest

from polynav.protocols.galileo.system_tasks import device_task
from tests.protocols.galileo.conftest import Harness

COVERED = {
    "GET /api/v1/system/slide_pose": "test_the_slide_homes_then_moves_to_the_ratio",
    "GET /api/v1/system/slide_move_to": "test_the_slide_homes_then_moves_to_the_ratio",
    "GET /api/v1/system/jacking_pose": "test_the_jacking_lifts_at_the_asked_speed",
    "GET /api/v1/system/jacking_move_to": "test_the_jacking_lifts_at_the_asked_speed",
    "GET /api/v1/system/jacking_angle": "test_the_jacking_turns_to_an_angle_in_either_frame",
    "GET /api/v1/system/jacking_angle_move_to":
        "test_the_jacking_turns_to_an_angle_in_either_frame",
}


def test_the_slide_homes_then_moves_to_the_ratio(galileo: Harness) -> None:
    assert galileo.ok("GET", "/system/slide_pose") == {"zero_status": 0, "current_pose": 0.0,
                                                       "pose_ratio": 0.0}
    task = galileo.ok("GET", "/system/slide_move_to", params={"pose": 0.5, "speed": 0})
    assert task["name"] == "slide_task" and task["state"] == "WORKING"
    action = task["current_task"]
    assert (action["type"], action["mode"], action["pose"], action["speed"], action["time"]) == (
        "slide_action", 3, 0.5, 0.0, 0)
    assert (action["state"], action["result"]) == ("WORKING", "")
    assert task["sub_tasks"] == [action]
    galileo.runtime.advance(6.0)  # homing: 0.17 m at 0.03 m/s
    mid = galileo.ok("GET", "/system/slide_pose")
    assert mid["zero_status"] == 1 and 0.0 < mid["pose_ratio"] < 0.5
    galileo.runtime.advance(6.0)  # 0.3 m at the default 0.05 m/s
    assert galileo.ok("GET", "/system/slide_pose") == pytest.approx(
        {"zero_status": 1, "current_pose": 0.3, "pose_ratio": 0.5})
    galileo.runtime.advance(0.1)
    done = galileo.ok("GET", "/task", params={"id": task["id"]})  # the task API reads it
    assert done["state"] == "COMPLETE" and done["progress"] == 1.0
    assert device_task(galileo.server.ctx, task["id"]) == done
    for params in ({"pose": 1.5e3}, {"pose": -0.1}, {}, {"pose": "high"},
                   {"pose": 0.5, "speed": -1}):
        assert galileo.get("/system/slide_move_to", **params).status_code == 400, params
    assert galileo.ok("GET", "/system/slide_pose")["pose_ratio"] == pytest.approx(0.5)


def test_the_jacking_lifts_at_the_asked_speed(galileo: Harness) -> None:
    galileo.ok("GET", "/system/jacking_move_to", params={"pose": 0})  # home (12 mm at 5 mm/s)
    galileo.runtime.advance(3.0)
    assert galileo.ok("GET", "/system/jacking_pose")["zero_status"] == 1
    task = galileo.ok("GET", "/system/jacking_move_to", params={"pose": 100, "speed": 0.02})
    assert task["name"] == "jacking_task" and task["current_task"]["pose"] == 1.0
    galileo.runtime.advance(1.5)
    assert galileo.ok("GET", "/system/jacking_pose")["current_pose"] == pytest.approx(0.03)
    galileo.runtime.advance(1.6)
    assert galileo.ok("GET", "/system/jacking_pose")["pose_ratio"] == pytest.approx(1.0)


def test_the_jacking_turns_to_an_angle_in_either_frame(galileo: Harness) -> None:
    assert galileo.ok("GET", "/system/jacking_angle") == {"zero_status": 0,
                                                          "current_angle": 0.0}
    task = galileo.ok("GET", "/system/jacking_angle_move_to", params={"angle": math.pi / 2})
    assert task["current_task"]["type"] == "jacking_rotate_action"
    assert task["current_task"]["mode"] == 1
    galileo.runtime.advance(5.0)  # home 0.4 rad at 0.3 rad/s, then pi/2 at 0.5 rad/s
    body = galileo.ok("GET", "/system/jacking_angle", params={"frame_id": "base_link"})
    assert body["zero_status"] == 1
    assert body["current_angle"] == pytest.approx(math.pi / 2)
    heading = galileo.runtime.status().pose.theta
    in_map = galileo.ok("GET", "/system/jacking_angle", params={"frame_id": "map"})
    assert in_map["current_angle"] == pytest.approx(
        math.remainder(math.pi / 2 + heading, 2 * math.pi))
    assert galileo.get("/system/jacking_angle", frame_id="odom").status_code == 400
    assert galileo.get("/system/jacking_angle_move_to").status_code == 400
    assert galileo.get("/system/jacking_angle_move_to", angle="nan").status_code == 400


def test_a_faulty_axis_reads_zero_status_minus_one_and_its_task_errors(galileo: Harness) -> None:
    task = galileo.ok("GET", "/system/slide_move_to", params={"pose": 1.0})
    galileo.runtime.advance(1.0)
    slide = galileo.runtime.peripherals.devices.slide
    galileo.runtime.run_between_ticks(
        lambda: slide.set_fault(galileo.runtime.now(), "motor overcurrent"))  # type: ignore[attr-defined]
    galileo.runtime.advance(0.2)
    assert galileo.ok("GET", "/system/slide_pose")["zero_status"] == -1
    failed = galileo.ok("GET", "/task", params={"id": task["id"]})
    assert failed["state"] == "ERROR"
    assert failed["current_task"]["state"] == "ERROR"
    assert failed["current_task"]["result"] == "motor overcurrent"
