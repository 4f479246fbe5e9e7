"""Navigation lifecycle, goals and tasks over real HTTP against a running polynav
(galileo-http-b §4, E27, E30, E31, E37, E49, E56; issue items 4, 11)."""

from __future__ import annotations

import math
from typing import Any

import pytest

from polynav.store.route_stops import RouteBook
from tests.protocols.galileo.conftest import Harness

COVERED = {
    "GET /api/v1/navigation/start": "test_start_navigation_on_map_and_path_from_a_target",
    "GET /api/v1/navigation/stop": "test_stop_answers_result_even_when_nothing_navigates",
    "GET /api/v1/navigation/pose": "test_pose_is_metres_and_degrees",
    "GET /api/v1/navigation/current_path": "test_start_navigation_on_map_and_path_from_a_target",
    "GET /api/v1/navigation/target_distance": "test_move_to_index_drives_there_and_completes",
    "GET /api/v1/navigation/move_to_index": "test_move_to_index_drives_there_and_completes",
    "POST /api/v1/navigation/start_nav_task": "test_start_nav_task_reaches_the_pose",
    "GET /api/v1/navigation/stop_nav_task": "test_stop_nav_task_cancels_the_task",
    "GET /api/v1/navigation/reload": "test_reload_switches_the_navigation_map",
    "GET /api/v1/navigation/switch_map": "test_switch_map_sets_the_next_start_map",
    "POST /api/v1/navigation/init_pose": "test_init_pose_relocalizes",
    "PUT /api/v1/navigation/update_map": "test_update_map_is_refused_on_and_reads_off",
    "GET /api/v1/navigation/update_map": "test_update_map_is_refused_on_and_reads_off",
    "GET /api/v1/navigation/start_schedule_mode": "test_schedule_mode_refuses_galileo_goals",
    "GET /api/v1/navigation/stop_schedule_mode": "test_schedule_mode_refuses_galileo_goals",
}


def _start(g: Harness, **params: Any) -> dict[str, Any]:
    body: dict[str, Any] = g.ok("GET", "/navigation/start", params=params)
    g.advance_until(lambda: g.runtime.status().mode == "navigating", 10.0)
    return body


def _wait_task(g: Harness, task_id: str, timeout: float = 120.0) -> dict[str, Any]:
    final = ("COMPLETE", "ERROR", "CANCELLED")
    state: dict[str, Any] = {}

    def done() -> bool:
        state.update(g.ok("GET", "/task", params={"id": task_id}))
        return state["state"] in final

    assert g.advance_until(done, timeout), state
    return state


def test_start_navigation_on_map_and_path_from_a_target(galileo: Harness) -> None:
    store = galileo.runtime.store
    default = RouteBook(store).route("floor1", "default")  # type: ignore[arg-type]
    assert default.stops[1].point == "lobby"
    body = galileo.ok("GET", "/navigation/start",
                      params={"map": "floor1", "path": "default", "start_index": 1})
    assert body == {"result": True, "description": ""}
    galileo.advance_until(lambda: galileo.runtime.status().mode == "navigating", 10.0)
    assert galileo.ok("GET", "/system/status") == {"status": "Navigating"}
    assert galileo.ok("GET", "/navigation/current_path") == {"map": "floor1", "path": "default"}
    status = galileo.ok("GET", "/system/galileo_status")
    assert status["navStatus"] == 1
    pose = galileo.runtime.status().pose
    assert math.hypot(pose.x - 5.5, pose.y - 12.5) < 0.3  # localized at "lobby"


def test_start_navigation_bad_input_changes_nothing(galileo: Harness) -> None:
    for params, word in (({"map": "nowhere"}, "nowhere"),
                         ({"map": "floor1", "path": "nopath"}, "nopath"),
                         ({"map": "floor1", "start_index": 999}, "index"),
                         ({"map": "floor1", "start_index": "x"}, "start_index"),
                         ({"map": "floor1", "start_index": -5}, "index")):
        body = galileo.ok("GET", "/navigation/start", params=params)
        assert body["result"] is False and word in body["description"], (params, body)
    assert galileo.runtime.status().mode == "free"


def test_stop_answers_result_even_when_nothing_navigates(galileo: Harness) -> None:
    body = galileo.ok("GET", "/navigation/stop")
    assert body["result"] is True and isinstance(body["description"], str)
    _start(galileo)
    assert galileo.ok("GET", "/navigation/stop") == {"result": True, "description": ""}
    galileo.runtime.advance(1.0)
    assert galileo.ok("GET", "/system/status") == {"status": "Free"}


def test_pose_is_metres_and_degrees(galileo: Harness) -> None:
    _start(galileo, map="floor1", start_index=2)  # front_desk, facing +y
    body = galileo.ok("GET", "/navigation/pose")
    assert set(body) == {"x", "y", "angle"}
    assert abs(body["x"] - 5.0) < 0.3 and abs(body["y"] - 6.0) < 0.3
    assert abs(body["angle"] - 90.0) < 6.0


def test_move_to_index_drives_there_and_completes(galileo: Harness) -> None:
    _start(galileo, map="floor1", path="default", start_index=1)
    task = galileo.ok("GET", "/navigation/move_to_index", params={"index": 2})
    assert task["state"] == "WORKING" and task["name"] == "navigation task"
    action = task["sub_tasks"][0]
    assert action["type"] == "nav_action" and action["index"] == 2
    assert (action["x"], action["y"]) == (5.0, 6.0)
    galileo.runtime.advance(1.0)
    status = galileo.ok("GET", "/system/galileo_status")
    assert (status["targetNumID"], status["targetStatus"]) == (2, 1)
    assert galileo.ok("GET", "/navigation/target_distance")["distance"] > 0.5
    final = _wait_task(galileo, task["id"])
    assert final["state"] == "COMPLETE", final
    pose = galileo.ok("GET", "/navigation/pose")
    assert math.hypot(pose["x"] - 5.0, pose["y"] - 6.0) < 0.1
    assert abs(pose["angle"] - 90.0) < math.degrees(0.1)
    status = galileo.ok("GET", "/system/galileo_status")
    assert (status["targetStatus"], status["angleGoalStatus"]) == (0, 1)
    assert galileo.ok("GET", "/navigation/target_distance") == {"distance": -1.0}


def test_move_to_index_bad_input_and_wrong_state(galileo: Harness) -> None:
    refused = galileo.get("/navigation/move_to_index", index=1)
    assert refused.status_code == 409  # not navigating
    _start(galileo, map="floor1")
    for params, status in (({}, 400), ({"index": "one"}, 400), ({"index": 99}, 400),
                           ({"index": 1, "path": "nopath"}, 404),
                           ({"index": 1, "map": "nomap"}, 404)):
        response = galileo.get("/navigation/move_to_index", **params)
        assert response.status_code == status, (params, response.text)
        assert response.json()["status"] == "error"
    assert galileo.runtime.status().navigation_state == "idle"


def test_start_nav_task_reaches_the_pose(galileo: Harness) -> None:
    _start(galileo, map="floor1", start_index=1)
    task = galileo.ok("POST", "/navigation/start_nav_task",
                      json={"x": 8.0, "y": 12.4, "theta": 0.0})
    assert [a["type"] for a in task["sub_tasks"]] == ["nav_action"]
    assert task["current_task"]["id"] == task["sub_tasks"][0]["id"]
    galileo.runtime.advance(0.5)
    assert galileo.ok("GET", "/system/galileo_status")["targetNumID"] == -2
    final = _wait_task(galileo, task["id"])
    assert final["state"] == "COMPLETE"
    pose = galileo.runtime.status().pose
    assert math.hypot(pose.x - 8.0, pose.y - 12.4) < 0.15
    bad = galileo.post("/navigation/start_nav_task", {"x": 1.0, "y": "north", "theta": 0})
    assert bad.status_code == 400 and "y" in bad.json()["description"]


def test_stop_nav_task_cancels_the_task(galileo: Harness) -> None:
    _start(galileo, map="floor1", start_index=1)
    assert galileo.ok("GET", "/navigation/stop_nav_task") is None
    task = galileo.ok("GET", "/navigation/move_to_index", params={"index": 5})
    galileo.runtime.advance(2.0)
    stopped = galileo.ok("GET", "/navigation/stop_nav_task")
    assert stopped["id"] == task["id"] and stopped["state"] == "CANCELLED"
    galileo.runtime.advance(1.0)
    assert galileo.ok("GET", "/task", params={"id": task["id"]})["state"] == "CANCELLED"
    assert galileo.ok("GET", "/system/galileo_status")["targetStatus"] == 0


def test_reload_switches_the_navigation_map(galileo: Harness) -> None:
    _start(galileo, map="floor1")
    body = galileo.ok("GET", "/navigation/reload", params={"map": "floor1", "path": "default"})
    assert body == {"status": "ok", "map": "floor1", "path": "default"}
    assert galileo.get("/navigation/reload").status_code == 400
    assert galileo.get("/navigation/reload", map="nomap").status_code == 404


def test_switch_map_sets_the_next_start_map(galileo: Harness) -> None:
    assert galileo.ok("GET", "/navigation/switch_map", params={"map_name": "floor2"}) == {
        "status": "ok"}
    assert galileo.ok("GET", "/navigation/current_path")["map"] == "floor2"
    assert galileo.get("/navigation/switch_map", map_name="nomap").status_code == 404
    galileo.ok("GET", "/navigation/switch_map", params={"map_name": "floor1"})
    _start(galileo)
    assert galileo.get("/navigation/switch_map", map_name="floor2").status_code == 409


def test_init_pose_relocalizes(galileo: Harness) -> None:
    assert galileo.post("/navigation/init_pose", {"x": 1, "y": 2, "z": 0}).status_code == 409
    _start(galileo, map="floor1", start_index=1)
    true_pose = galileo.runtime.simulation.true_pose
    body = galileo.ok("POST", "/navigation/init_pose",
                      json={"x": true_pose.x, "y": true_pose.y, "z": 0,
                            "theta": true_pose.theta})
    assert body == {"status": "ok"}
    assert galileo.post("/navigation/init_pose", {"x": 1}).status_code == 400


def test_update_map_is_refused_on_and_reads_off(galileo: Harness) -> None:
    assert galileo.ok("GET", "/navigation/update_map") == {"enabled": False}
    assert galileo.put("/navigation/update_map", {"enabled": True}).status_code == 409
    assert galileo.ok("PUT", "/navigation/update_map", json={"enabled": False}) == {
        "enabled": False}
    assert galileo.put("/navigation/update_map", {}).status_code == 400


def test_schedule_mode_refuses_galileo_goals(galileo: Harness) -> None:
    body = galileo.ok("GET", "/navigation/start_schedule_mode")
    assert body["result"] is True
    galileo.advance_until(lambda: galileo.runtime.status().mode == "navigating", 10.0)
    refused = galileo.get("/navigation/move_to_index", index=1)
    assert refused.status_code == 409 and "dispatch" in refused.json()["description"]
    assert galileo.ok("GET", "/navigation/stop_schedule_mode")["result"] is True
    galileo.runtime.advance(1.0)
    assert galileo.ok("GET", "/system/status") == {"status": "Free"}
    again = galileo.ok("GET", "/navigation/stop_schedule_mode")
    assert again["result"] is False


def test_task_polling_reads_a_snapshot_without_the_runtime(
    galileo: Harness, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Issue item 11: scripts poll ``GET /task?id=`` in a tight loop, so it must not wait for
    the runtime: it answers from the snapshot the task book's last poll left, even while every
    runtime command would fail."""
    _start(galileo, map="floor1", start_index=1)
    task = galileo.ok("GET", "/navigation/move_to_index", params={"index": 2})
    galileo.runtime.advance(1.0)
    expected = galileo.ok("GET", "/task", params={"id": task["id"]})

    def no_runtime(*args: object, **kwargs: object) -> None:
        raise AssertionError("GET /task went to the runtime")

    with monkeypatch.context() as patched:
        patched.setattr(galileo.runtime._loop, "call", no_runtime)
        patched.setattr(galileo.runtime, "status", no_runtime)
        for _ in range(20):
            assert galileo.ok("GET", "/task", params={"id": task["id"]}) == expected
    assert expected["state"] == "WORKING"
    assert _wait_task(galileo, task["id"])["state"] == "COMPLETE"
