"""Goals on another map across a direct connection, and the multi-map task (galileo-http-b
§1.6, E27, E30, E57): a goal on another map is one ``nav_action``; the runtime's router drives
the robot to the exit point, switches maps, and goes on."""

from __future__ import annotations

import math
from typing import Any

from tests.protocols.galileo.conftest import Harness

COVERED = {
    "POST /api/v1/navigation/multi_map_task": "test_multi_map_task_is_built_not_run",
}

CONNECT: dict[str, Any] = {
    "points": [{"map": "floor1", "path": "default", "index": 11},   # corridor_west
               {"map": "floor2", "path": "default", "index": 5}],   # corridor_west
    "type": "direct"}


def _wait(g: Harness, task_id: str, timeout: float) -> dict[str, Any]:
    out: dict[str, Any] = {}

    def done() -> bool:
        out.update(g.ok("GET", "/task", params={"id": task_id}))
        return out["state"] in ("COMPLETE", "ERROR", "CANCELLED")

    assert g.advance_until(done, timeout, step=0.2), out
    return out


def test_move_to_index_on_another_map_crosses_the_connection(galileo: Harness) -> None:
    galileo.ok("POST", "/navigation/point_connections", json=CONNECT)
    galileo.ok("GET", "/navigation/start", params={"map": "floor1", "start_index": 1})
    galileo.advance_until(lambda: galileo.runtime.status().mode == "navigating", 10.0)
    task = galileo.ok("GET", "/navigation/move_to_index",
                      params={"map": "floor2", "path": "default", "index": 1})  # lounge
    assert [(a["type"], a["map"], a["index"]) for a in task["sub_tasks"]] == [
        ("nav_action", "floor2", 1)]
    final = _wait(galileo, task["id"], 240.0)
    assert final["state"] == "COMPLETE", final
    status = galileo.runtime.status()
    assert status.map == "floor2"
    pose = galileo.ok("GET", "/navigation/pose")
    assert math.hypot(pose["x"] - 4.0, pose["y"] - 11.0) < 0.1
    assert galileo.ok("GET", "/navigation/current_path")["map"] == "floor2"


def test_goal_on_an_unconnected_map_is_refused(galileo: Harness) -> None:
    galileo.runtime.store.set_connections([])  # no lift, no direct connection: no way up
    galileo.ok("GET", "/navigation/start", params={"map": "floor1", "start_index": 1})
    galileo.advance_until(lambda: galileo.runtime.status().mode == "navigating", 10.0)
    refused = galileo.get("/navigation/move_to_index", map="floor2", index=1)
    assert refused.status_code == 409 and "no lift" in refused.json()["description"]
    refused = galileo.post("/navigation/start_nav_task",
                           {"x": 4.0, "y": 11.0, "theta": 0.0, "map": "floor2"})
    assert refused.status_code == 409
    assert galileo.runtime.status().navigation_state == "idle"


def test_multi_map_task_is_built_not_run(galileo: Harness) -> None:
    galileo.ok("POST", "/navigation/point_connections", json=CONNECT)
    body = {"from": {"map": "floor1", "path": "default", "index": 1},
            "to": {"map": "floor2", "path": "default", "index": 2}}
    task = galileo.ok("POST", "/navigation/multi_map_task", json=body)
    assert task["state"] == "WAITTING" and task["current_task"] is None
    assert [a["type"] for a in task["sub_tasks"]] == ["nav_action", "nav_action"]
    assert task["sub_tasks"][-1]["index"] == 2 and task["sub_tasks"][-1]["map"] == "floor2"
    assert galileo.ok("GET", "/task", params={"id": task["id"]})["state"] == "WAITTING"
    assert galileo.runtime.status().navigation_state == "idle"
    same = galileo.ok("POST", "/navigation/multi_map_task", json={
        "from": body["from"], "to": {"map": "floor1", "path": "default", "index": 3}})
    assert [a["type"] for a in same["sub_tasks"]] == ["nav_action", "nav_action"]
    for bad, status in (({"from": body["from"]}, 400),
                        ({**body, "to": {"map": "floor2", "index": 99}}, 400),
                        ({**body, "to": {"map": "nomap", "index": 0}}, 404),
                        ({**body, "to": "floor2"}, 400)):
        response = galileo.post("/navigation/multi_map_task", bad)
        assert response.status_code == status, (bad, response.text)
