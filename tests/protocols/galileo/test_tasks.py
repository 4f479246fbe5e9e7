"""Galileo tasks, behavior trees and actions over real HTTP against a running polynav
(galileo-tasks-bt-ws §4, §5, §7), on the robot's task engine.

The black box: a client with a token (``no_token_check: false``) creates a task of three
``nav_action``s, starts it, polls ``GET /task?id=`` until ``COMPLETE``, and each point is
reached (the simulator's true pose) within 0.1 m and 0.1 rad; a fallback over a goal that
cannot be reached and a real one ends ``COMPLETE``.
"""

from __future__ import annotations

import json
import math
from typing import Any

from polynav.protocols.galileo.auth import ServiceSettings
from polynav.runtime.robot_runtime import RobotRuntime
from tests.protocols.galileo.conftest import Harness, serving
from tests.protocols.galileo.state import digest

COVERED = {
    "GET /api/v1/task": "test_three_nav_actions_reach_each_point_with_a_token",
    "POST /api/v1/task": "test_three_nav_actions_reach_each_point_with_a_token",
    "GET /api/v1/task/start": "test_three_nav_actions_reach_each_point_with_a_token",
    "GET /api/v1/task/pause": "test_pause_stops_the_robot_resume_goes_on_stop_cancels",
    "GET /api/v1/task/resume": "test_pause_stops_the_robot_resume_goes_on_stop_cancels",
    "GET /api/v1/task/stop": "test_pause_stops_the_robot_resume_goes_on_stop_cancels",
    "GET /api/v1/task/loop": "test_loop_flag_repeats_the_task_until_cleared",
    "PUT /api/v1/task": "test_put_and_delete_change_tasks_and_actions_that_do_not_run",
    "DELETE /api/v1/task": "test_put_and_delete_change_tasks_and_actions_that_do_not_run",
    "GET /api/v1/action": "test_put_and_delete_change_tasks_and_actions_that_do_not_run",
    "POST /api/v1/action": "test_auto_task_waits_for_update_wait_req",
    "PUT /api/v1/action": "test_put_and_delete_change_tasks_and_actions_that_do_not_run",
    "DELETE /api/v1/action": "test_put_and_delete_change_tasks_and_actions_that_do_not_run",
    "GET /api/v1/action/update_wait_req": "test_auto_task_waits_for_update_wait_req",
}

POINTS = [(5.5, 12.5, 0.0), (13.5, 12.4, 0.0), (8.0, 8.5, math.pi / 2)]
ENDED = ("COMPLETE", "ERROR", "FAIL", "CANCELLED")


def _navigate(g: Harness, index: int = 2) -> None:
    g.ok("GET", "/navigation/start", params={"map": "floor1", "start_index": index})
    assert g.advance_until(lambda: g.runtime.status().mode == "navigating", 10.0)
    g.runtime.advance(1.0)


def _task(g: Harness, task_id: str) -> dict[str, Any]:
    body = g.ok("GET", "/task", params={"id": task_id})
    assert isinstance(body, dict)
    return body


def _until_ended(g: Harness, task_id: str, timeout: float = 240.0) -> dict[str, Any]:
    out: dict[str, Any] = {}

    def done() -> bool:
        out.update(_task(g, task_id))
        return out["state"] in ENDED

    assert g.advance_until(done, timeout, step=0.2), out
    return out


def _nav(x: float, y: float, theta: float) -> dict[str, Any]:
    return {"type": "nav_action", "x": x, "y": y, "theta": theta}


def _true_error(rt: RobotRuntime, x: float, y: float, theta: float) -> tuple[float, float]:
    truth = rt.simulation.true_pose
    return (math.hypot(truth.x - x, truth.y - y),
            abs(math.remainder(truth.theta - theta, math.tau)))


def test_three_nav_actions_reach_each_point_with_a_token(runtime: RobotRuntime) -> None:
    config = runtime.store.data_dir / "galileo" / "config.json"
    config.parent.mkdir(parents=True, exist_ok=True)
    config.write_text(json.dumps({**ServiceSettings().to_dict(), "no_token_check": False}),
                      encoding="utf-8")
    with serving(runtime) as g:
        assert g.get("/task").status_code == 401
        g.token = g.ok("GET", "/token", params={"username": "admin", "password": "admin"}
                       )["token"]
        _navigate(g)
        made = g.ok("POST", "/task", json={"name": "three", "loop_flag": False,
                                           "sub_tasks": [_nav(*p) for p in POINTS]})
        assert (made["state"], made["current_task"], made["progress"]) == ("WAITTING", None, 0)
        assert made["loop_flag"] is False and "control_type" not in made
        first = made["sub_tasks"][0]
        assert (first["type"], first["state"], first["result"], first["x"]) == (
            "nav_action", "WAITTING", "", 5.5)
        assert (first["current_location"], first["current_distance"], first["timeout"]) == (
            {"x": -1, "y": -1, "theta": -1}, -1, 0)
        assert made["id"] in [t["id"] for t in g.ok("GET", "/task")]
        started = g.ok("GET", "/task/start", params={"id": made["id"]})
        assert started["state"] == "WORKING"
        assert started["current_task"]["id"] == first["id"]
        g.runtime.advance(1.0)
        running = _task(g, made["id"])["sub_tasks"][0]
        assert running["state"] == "WORKING" and running["current_location"]["x"] != -1
        errors = []
        for i, point in enumerate(POINTS):
            assert g.runtime.advance_until(
                lambda i=i: g.runtime.tasks.get(made["id"])["tree"]["children"][i]["state"]
                in ENDED, 180.0)
            errors.append(_true_error(g.runtime, *point))
            assert _task(g, made["id"])["sub_tasks"][i]["state"] == "COMPLETE"
        final = _until_ended(g, made["id"])
        assert final["state"] == "COMPLETE" and final["progress"] == 1
        assert final["current_task"] is None
        assert max(d for d, _ in errors) < 0.1, errors
        assert max(a for _, a in errors) < 0.1, errors


def test_a_fallback_over_an_unreachable_goal_reaches_the_real_point(galileo: Harness) -> None:
    _navigate(galileo)
    tree = {"name": "fb", "control_type": "fallback",
            "sub_tasks": [_nav(-50.0, -50.0, 0.0), _nav(5.5, 12.5, 0.0)]}
    made = galileo.ok("POST", "/task", json=tree)
    assert made["control_type"] == "fallback" and made["loop_flag"] is False
    galileo.ok("GET", "/task/start", params={"id": made["id"]})
    final = _until_ended(galileo, made["id"])
    assert final["state"] == "COMPLETE", final
    assert [a["state"] for a in final["sub_tasks"]] == ["FAIL", "COMPLETE"]
    assert final["sub_tasks"][0]["result"]
    assert _true_error(galileo.runtime, 5.5, 12.5, 0.0)[0] < 0.1
    # The same unreachable goal in a plain task: the vendor's plain tasks know ERROR only.
    plain = galileo.ok("POST", "/task", json={"name": "p", "sub_tasks": [
        _nav(-50.0, -50.0, 0.0)]})
    galileo.ok("GET", "/task/start", params={"id": plain["id"]})
    ended = _until_ended(galileo, plain["id"])
    assert (ended["state"], ended["sub_tasks"][0]["state"]) == ("ERROR", "ERROR")
    assert ended["current_task"]["id"] == ended["sub_tasks"][0]["id"]


def test_pause_stops_the_robot_resume_goes_on_stop_cancels(galileo: Harness) -> None:
    _navigate(galileo)
    made = galileo.ok("POST", "/task", json={"name": "far", "sub_tasks": [
        _nav(13.5, 12.4, 0.0)]})
    refused = galileo.get("/task/pause", id=made["id"])
    assert refused.status_code == 409 and refused.json()["status"] == "error"
    galileo.ok("GET", "/task/start", params={"id": made["id"]})
    galileo.runtime.advance(5.0)
    paused = galileo.ok("GET", "/task/pause", params={"id": made["id"]})
    assert paused["state"] == "PAUSED" and paused["sub_tasks"][0]["state"] == "PAUSED"
    galileo.runtime.advance(2.0)
    still = galileo.runtime.simulation.true_pose
    galileo.runtime.advance(3.0)
    moved = galileo.runtime.simulation.true_pose
    assert math.hypot(moved.x - still.x, moved.y - still.y) < 0.01
    assert galileo.get("/task/resume", id="nope").status_code == 404
    resumed = galileo.ok("GET", "/task/resume", params={"id": made["id"]})
    assert resumed["state"] == "WORKING"
    galileo.runtime.advance(3.0)
    going = galileo.runtime.simulation.true_pose
    assert math.hypot(going.x - moved.x, going.y - moved.y) > 0.2
    stopped = galileo.ok("GET", "/task/stop", params={"id": made["id"]})
    assert stopped["state"] == "CANCELLED" and stopped["sub_tasks"][0]["state"] == "CANCELLED"
    galileo.runtime.advance(2.0)
    assert galileo.runtime.status().navigation_state != "running"
    assert _task(galileo, made["id"])["state"] == "CANCELLED"
    # Without id: the running task is cancelled, answered in an array; none: [].
    again = galileo.ok("GET", "/task/start", params={"id": made["id"]})
    assert again["state"] == "WORKING"
    assert [t["id"] for t in galileo.ok("GET", "/task/stop")] == [made["id"]]
    assert galileo.ok("GET", "/task/stop") == []


def test_loop_flag_repeats_the_task_until_cleared(galileo: Harness) -> None:
    made = galileo.ok("POST", "/task", json={"name": "ticks", "sub_tasks": [
        {"type": "sleep_action", "wait_time": 1}, {"type": "sleep_action", "wait_time": 1}]})
    looped = galileo.ok("GET", "/task/loop", params={"id": made["id"], "loop_flag": "true"})
    assert looped["loop_flag"] is True and looped["state"] == "WAITTING"
    galileo.ok("GET", "/task/start", params={"id": made["id"]})
    assert galileo.advance_until(lambda: _task(galileo, made["id"])["loop_count"] >= 2, 20.0)
    assert _task(galileo, made["id"])["state"] == "WORKING"
    cleared = galileo.ok("GET", "/task/loop", params={"id": made["id"], "loop_flag": 0})
    assert cleared["loop_flag"] is False
    assert _until_ended(galileo, made["id"], 10.0)["state"] == "COMPLETE"
    bad = galileo.get("/task/loop", id=made["id"], loop_flag="maybe")
    assert bad.status_code == 400 and "loop_flag" in bad.json()["description"]


def test_auto_task_waits_for_update_wait_req(galileo: Harness) -> None:
    auto = galileo.ok("POST", "/action", json={"type": "wait_req_action"})
    assert (auto["name"], auto["state"], auto["current_task"]) == ("auto task", "WAITTING", None)
    assert auto["id"] not in [t["id"] for t in galileo.ok("GET", "/task")]
    wait = auto["sub_tasks"][0]
    assert (wait["type"], wait["state"], wait["result"], wait["progress"]) == (
        "wait_req_action", "WAITTING", "", 0)
    grown = galileo.ok("POST", "/action", json={"type": "sleep_action", "wait_time": 2,
                                                "task_id": auto["id"]})
    assert [a["type"] for a in grown["sub_tasks"]] == ["wait_req_action", "sleep_action"]
    assert grown["sub_tasks"][0]["id"] == wait["id"]
    galileo.ok("GET", "/task/start", params={"id": auto["id"]})
    galileo.runtime.advance(3.0)
    assert _task(galileo, auto["id"])["current_task"]["id"] == wait["id"]
    refused = galileo.post("/action", {"type": "sleep_action", "wait_time": 1,
                                       "task_id": auto["id"]})
    assert refused.status_code == 409  # not while it runs
    assert galileo.ok("GET", "/action/update_wait_req") == {"status": "OK"}
    done = _until_ended(galileo, auto["id"], 10.0)
    assert done["state"] == "COMPLETE"
    assert [a["state"] for a in done["sub_tasks"]] == ["COMPLETE", "COMPLETE"]


def test_put_and_delete_change_tasks_and_actions_that_do_not_run(galileo: Harness) -> None:
    made = galileo.ok("POST", "/task", json={"name": "t", "sub_tasks": [
        {"type": "sleep_action", "wait_time": 1}]})
    changed = galileo.ok("PUT", "/task", json={
        "id": made["id"], "name": "renamed", "loop_flag": True,
        "sub_tasks": [{"type": "sleep_action", "wait_time": 2},
                      {"type": "tts_action", "text": "hello"}]})
    assert (changed["id"], changed["name"], changed["loop_flag"]) == (made["id"], "renamed", True)
    assert [a["type"] for a in changed["sub_tasks"]] == ["sleep_action", "tts_action"]
    sleep = changed["sub_tasks"][0]
    assert galileo.ok("GET", "/action", params={"id": sleep["id"]}) == sleep
    assert sleep["id"] in [a["id"] for a in galileo.ok("GET", "/action")]
    edited = galileo.ok("PUT", "/action", json={"id": sleep["id"], "wait_time": 5})
    assert (edited["id"], edited["wait_time"]) == (sleep["id"], 5)
    assert _task(galileo, made["id"])["sub_tasks"][0]["wait_time"] == 5
    bad = galileo.put("/action", {"id": sleep["id"], "wait_time": -1})
    assert bad.status_code == 400 and "wait_time" in bad.json()["description"]
    assert galileo.ok("DELETE", "/action", params={"id": sleep["id"]}) == {"status": "ok"}
    left = _task(galileo, made["id"])["sub_tasks"]
    assert [a["type"] for a in left] == ["tts_action"]
    last = galileo.delete("/action", id=left[0]["id"])
    assert last.status_code == 400  # a task keeps one action at least
    assert galileo.get("/action", id=sleep["id"]).status_code == 404
    galileo.ok("GET", "/task/start", params={"id": made["id"]})
    assert galileo.put("/task", {"id": made["id"], "name": "x"}).status_code == 409
    assert galileo.delete("/task", id=made["id"]).status_code == 409
    galileo.ok("GET", "/task/stop", params={"id": made["id"]})
    assert galileo.ok("DELETE", "/task", params={"id": made["id"]}) == {"status": "ok"}
    assert galileo.get("/task", id=made["id"]).status_code == 404


def test_bad_input_is_refused_in_the_dialects_error_body_and_changes_nothing(
        galileo: Harness) -> None:
    _navigate(galileo)
    running = galileo.ok("POST", "/task", json={"name": "r", "sub_tasks": [
        {"type": "sleep_action", "wait_time": 30}]})
    galileo.ok("GET", "/task/start", params={"id": running["id"]})
    galileo.runtime.advance(0.5)
    cases: list[tuple[str, str, dict[str, Any], int, str]] = [
        ("POST", "/task", {"name": "u", "sub_tasks": [{"type": "fly_action"}]}, 400,
         "fly_action"),
        ("POST", "/task", {"name": "p", "sub_tasks": [
            {"type": "sleep_action", "wait_time": "long"}]}, 400, "wait_time"),
        ("POST", "/task", {"name": "f", "control_type": "fallback", "sub_tasks": [
            {"type": "sleep_action", "wait_time": 1}] * 3}, 400, "fallback"),
        ("POST", "/task", {"sub_tasks": [{"type": "sleep_action", "wait_time": 1}]}, 400,
         "name"),
        ("POST", "/task", {"name": "k", "control_type": "sideways", "sub_tasks": [
            {"type": "sleep_action", "wait_time": 1}]}, 400, "sideways"),
        ("POST", "/action", {"type": "fly_action"}, 400, "fly_action"),
        ("POST", "/action", {"type": "nav_action", "x": 1}, 400, "y"),
        ("POST", "/action", {"type": "sleep_action", "wait_time": 1, "task_id": "nope"}, 404,
         "nope"),
        ("GET", "/task", {"id": "nope"}, 404, "nope"),
        ("GET", "/task/start", {"id": "nope"}, 404, "nope"),
        ("GET", "/task/start", {"id": running["id"]}, 409, "WORKING"),
        ("GET", "/task/resume", {"id": running["id"]}, 409, "PAUSED"),
        ("GET", "/action", {"id": "nope"}, 404, "nope"),
        ("PUT", "/task", {"id": running["id"], "sub_tasks": [
            {"type": "sleep_action", "wait_time": 1}]}, 409, "stop it first"),
        ("DELETE", "/task", {"id": "nope"}, 404, "nope"),
        ("DELETE", "/action", {"id": running["sub_tasks"][0]["id"]}, 409, "stop it first"),
    ]
    for method, path, body, status, words in cases:
        before = digest(galileo.runtime, galileo.server)
        if method in ("POST", "PUT"):
            reply = galileo.request(method, path, json=body)
        else:
            reply = galileo.request(method, path, params=body)
        assert reply.status_code == status, (method, path, body, reply.text)
        assert reply.json()["status"] == "error", reply.json()
        assert words in reply.json()["description"], (words, reply.json())
        assert digest(galileo.runtime, galileo.server) == before, (method, path, body)
    assert _task(galileo, running["id"])["state"] == "WORKING"
