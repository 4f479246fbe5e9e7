"""Local-move tasks over real HTTP (galileo-http-b §12, E58–E62)."""

from __future__ import annotations

import math
from typing import Any

from tests.protocols.galileo.conftest import Harness

COVERED = {
    "GET /api/v1/navigation/start_local_move": "test_local_move_turns_then_drives",
    "GET /api/v1/navigation/start_nav_and_local_move": "test_nav_then_local_move",
    "GET /api/v1/navigation/start_local_move_target": "test_local_move_to_a_pose_in_base_link",
    "GET /api/v1/navigation/start_local_move_index": "test_local_move_to_a_target_point",
    "GET /api/v1/navigation/start_nav_local_move_io": "test_nav_local_move_then_io",
}


def _navigate(g: Harness, index: int = 1) -> None:
    g.ok("GET", "/navigation/start", params={"map": "floor1", "start_index": index})
    g.advance_until(lambda: g.runtime.status().mode == "navigating", 10.0)
    g.runtime.advance(1.0)


def _finish(g: Harness, task: dict[str, Any], timeout: float = 120.0) -> dict[str, Any]:
    out: dict[str, Any] = {}

    def done() -> bool:
        out.update(g.ok("GET", "/task", params={"id": task["id"]}))
        return out["state"] in ("COMPLETE", "ERROR", "CANCELLED")

    assert g.advance_until(done, timeout)
    return out


def test_local_move_turns_then_drives(galileo: Harness) -> None:
    _navigate(galileo)  # lobby, facing +x, corridor ahead
    before = galileo.runtime.simulation.true_pose
    task = galileo.ok("GET", "/navigation/start_local_move",
                      params={"distance": 0.5, "angle": math.pi / 2, "method": 0})
    action = task["sub_tasks"][0]
    assert action["type"] == "local_move_action" and action["distance"] == 0.5
    assert _finish(galileo, task)["state"] == "COMPLETE"
    after = galileo.runtime.simulation.true_pose
    assert abs(math.remainder(after.theta - before.theta - math.pi / 2, math.tau)) < 0.1
    assert abs(after.y - before.y - 0.5) < 0.1 and abs(after.x - before.x) < 0.1
    for bad in ({"distance": 1, "angle": 0}, {"distance": "x", "angle": 0, "method": 0},
                {"distance": 20, "angle": 0, "method": 0},
                {"distance": 1, "angle": 0, "method": 7}):
        assert galileo.get("/navigation/start_local_move", **bad).status_code == 400


def test_nav_then_local_move(galileo: Harness) -> None:
    _navigate(galileo)
    task = galileo.ok("GET", "/navigation/start_nav_and_local_move",
                      params={"index": 11, "distance": -0.4, "angle": 0, "method": 1})
    assert [a["type"] for a in task["sub_tasks"]] == ["nav_action", "local_move_action"]
    assert _finish(galileo, task, 180.0)["state"] == "COMPLETE"
    pose = galileo.runtime.simulation.true_pose
    assert abs(pose.x - (13.5 - 0.4)) < 0.15 and abs(pose.y - 12.4) < 0.15


def test_local_move_to_a_pose_in_base_link(galileo: Harness) -> None:
    _navigate(galileo)
    before = galileo.runtime.simulation.true_pose
    task = galileo.ok("GET", "/navigation/start_local_move_target", params={
        "x": 0.6, "y": 0.0, "theta": 0.0, "frame_id": "base_link", "xy_tolerance": 0.05,
        "yaw_tolerance": 0.05, "timeout": 30, "start_rotate_enable": "true",
        "target_rotate_enable": 1})
    assert task["sub_tasks"][0]["type"] == "local_move_target_action"
    assert _finish(galileo, task)["state"] == "COMPLETE"
    after = galileo.runtime.simulation.true_pose
    assert abs(math.hypot(after.x - before.x, after.y - before.y) - 0.6) < 0.1
    bad = galileo.get("/navigation/start_local_move_target", x=1, y=0, theta=0,
                      frame_id="odom", xy_tolerance=0.1, yaw_tolerance=0.1, timeout=5,
                      start_rotate_enable=1, target_rotate_enable=1)
    assert bad.status_code == 400 and "frame_id" in bad.json()["description"]


def test_local_move_to_a_target_point(galileo: Harness) -> None:
    points = "5.5 12.5 0 0 0.1 0.1 0\n6.3 12.5 0 1.57 0.05 0.05 0\n"
    galileo.ok("POST", "/navigation/nav_points",
               json={"map_name": "floor1", "path_name": "dock", "path_data": points})
    galileo.ok("GET", "/navigation/start", params={"map": "floor1", "path": "dock",
                                                    "start_index": 0})
    galileo.runtime.advance(2.0)
    task = galileo.ok("GET", "/navigation/start_local_move_index",
                      params={"index": 1, "start_rotate_enable": True,
                              "target_rotate_enable": True})
    assert _finish(galileo, task)["state"] == "COMPLETE"
    pose = galileo.runtime.simulation.true_pose
    assert math.hypot(pose.x - 6.3, pose.y - 12.5) < 0.12
    assert abs(math.remainder(pose.theta - 1.57, math.tau)) < 0.1
    assert galileo.get("/navigation/start_local_move_index", index=5, start_rotate_enable=1,
                       target_rotate_enable=1).status_code == 400


def test_nav_local_move_then_io(galileo: Harness) -> None:
    _navigate(galileo)
    assert galileo.ok("GET", "/system/io")["out2"] == "-1"
    params = {"index": 11, "distance": -0.4, "angle": 0, "method": 0, "level": "1",
              "port": "2"}
    task = galileo.ok("GET", "/navigation/start_nav_local_move_io", params=params)
    assert task["state"] == "WORKING"
    assert [a["type"] for a in task["sub_tasks"]] == ["nav_action", "local_move_action",
                                                      "io_action"]
    io = task["sub_tasks"][2]
    assert (io["level"], io["port"], io["state"]) == ("1", "2", "WAITTING")
    galileo.runtime.advance(2.0)
    assert galileo.ok("GET", "/system/io")["out2"] == "-1"  # not before the moves end
    done = _finish(galileo, task, 180.0)
    assert done["state"] == "COMPLETE"
    assert [a["state"] for a in done["sub_tasks"]] == ["COMPLETE"] * 3
    pose = galileo.runtime.simulation.true_pose
    assert abs(pose.x - (13.5 - 0.4)) < 0.15 and abs(pose.y - 12.4) < 0.15
    io_state = galileo.ok("GET", "/system/io")
    assert (io_state["out1"], io_state["out2"], io_state["out3"]) == ("-1", "1", "-1")
    # ints are accepted as well; level 0 sets the port low again
    task = galileo.ok("GET", "/navigation/start_nav_local_move_io", params={
        **params, "level": 0, "port": 2, "distance": 0.0})
    assert _finish(galileo, task, 60.0)["state"] == "COMPLETE"
    assert galileo.ok("GET", "/system/io")["out2"] == "0"


def test_nav_local_move_io_refuses_bad_input_and_changes_nothing(galileo: Harness) -> None:
    _navigate(galileo)
    before = galileo.runtime.simulation.true_pose
    tasks_before = galileo.ok("GET", "/task")
    good = {"index": 11, "distance": -0.4, "angle": 0, "method": 0, "level": "1", "port": "2"}
    for change, field in (({"port": "4"}, "port"), ({"port": "0"}, "port"),
                          ({"level": "2"}, "level"), ({"level": "high"}, "level"),
                          ({"index": 99}, "index"), ({"method": 3}, "method"),
                          ({"port": None}, "port"), ({"distance": "x"}, "distance")):
        params = {k: v for k, v in {**good, **change}.items() if v is not None}
        reply = galileo.get("/navigation/start_nav_local_move_io", **params)
        assert reply.status_code == 400, (change, reply.text)
        assert field in reply.json()["description"], (change, reply.json())
    galileo.runtime.advance(2.0)
    after = galileo.runtime.simulation.true_pose
    assert abs(after.x - before.x) < 0.02 and abs(after.y - before.y) < 0.02
    assert galileo.ok("GET", "/task") == tasks_before
    assert galileo.ok("GET", "/system/io")["out2"] == "-1"
