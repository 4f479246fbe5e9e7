"""Charging and loop tasks over real HTTP (galileo-http-b E28, E29, E32–E36)."""

from __future__ import annotations

import math
from typing import Any

from tests.protocols.galileo.conftest import Harness

COVERED = {
    "GET /api/v1/navigation/go_charge": "test_go_charge_finds_docks_and_charges",
    "GET /api/v1/navigation/stop_charge": "test_stop_charge_cancels_the_charge_task",
    "GET /api/v1/navigation/charge_pose": "test_charge_pose_reads_and_saves_the_pile",
    "POST /api/v1/navigation/charge_pose": "test_charge_pose_reads_and_saves_the_pile",
    "GET /api/v1/navigation/loop_task": "test_loop_task_visits_the_points_round_after_round",
    "POST /api/v1/navigation/loop_task": "test_loop_task_visits_the_points_round_after_round",
    "DELETE /api/v1/navigation/loop_task": "test_loop_task_visits_the_points_round_after_round",
}


def _navigate(g: Harness, **params: Any) -> None:
    g.ok("GET", "/navigation/start", params={"map": "floor1", **params})
    g.advance_until(lambda: g.runtime.status().mode == "navigating", 10.0)


def test_charge_pose_reads_and_saves_the_pile(galileo: Harness) -> None:
    assert galileo.ok("GET", "/navigation/charge_pose") == {"x": 0.8, "y": 14.0,
                                                            "theta": math.pi}
    assert galileo.post("/navigation/charge_pose").status_code == 409  # not navigating
    _navigate(galileo, start_index=1)
    saved = galileo.ok("POST", "/navigation/charge_pose")
    pose = galileo.runtime.status().pose
    assert math.hypot(saved["x"] - pose.x, saved["y"] - pose.y) < 1e-6
    charger = galileo.runtime.store.point("floor1", "charger")
    assert (charger.pose.x, charger.pose.y) == (saved["x"], saved["y"])
    assert galileo.ok("GET", "/navigation/charge_pose") == saved


def test_go_charge_finds_docks_and_charges(galileo: Harness) -> None:
    assert galileo.get("/navigation/go_charge").status_code == 409
    _navigate(galileo, start_index=1)
    task = galileo.ok("GET", "/navigation/go_charge")
    assert task["name"] == "charge task" and task["sub_tasks"][0]["type"] == "charge_action"
    seen: set[int] = set()

    def done() -> bool:
        seen.add(galileo.ok("GET", "/system/galileo_status")["chargeStatus"])
        state = galileo.ok("GET", "/task", params={"id": task["id"]})["state"]
        return state in ("COMPLETE", "ERROR")

    assert galileo.advance_until(done, 180.0)
    assert galileo.ok("GET", "/task", params={"id": task["id"]})["state"] == "COMPLETE"
    assert 3 in seen and 4 in seen
    galileo.runtime.advance(2.0)
    assert galileo.ok("GET", "/system/galileo_status")["chargeStatus"] in (1, 2)
    assert galileo.runtime.status().charging


def test_stop_charge_cancels_the_charge_task(galileo: Harness) -> None:
    assert galileo.ok("GET", "/navigation/stop_charge") == {"status": "ok", "task": None}
    _navigate(galileo, start_index=3)  # office_1, far from the pile
    task = galileo.ok("GET", "/navigation/go_charge")
    galileo.runtime.advance(2.0)
    body = galileo.ok("GET", "/navigation/stop_charge")
    assert body["status"] == "ok" and body["task"]["id"] == task["id"]
    assert body["task"]["state"] == "CANCELLED"
    galileo.runtime.advance(1.0)
    assert galileo.ok("GET", "/system/galileo_status")["chargeStatus"] == 0


def test_loop_task_visits_the_points_round_after_round(galileo: Harness) -> None:
    points = "5.5 12.5 0 0 0.1 0.1 0\n8.0 12.4 0 3.14 0.1 0.1 0\n"
    galileo.ok("POST", "/navigation/nav_points",
               json={"map_name": "floor1", "path_name": "loop", "path_data": points})
    assert galileo.post("/navigation/loop_task", {"wait_time": 1}).status_code == 409
    _navigate(galileo, path="loop", start_index=0)
    assert galileo.ok("GET", "/navigation/loop_task") is None
    task = galileo.ok("POST", "/navigation/loop_task", json={"wait_time": 1})
    assert task["loop_flag"] is True
    assert [a["type"] for a in task["sub_tasks"]] == ["nav_action", "sleep_action"] * 2
    assert galileo.post("/navigation/loop_task", {"wait_time": 1}).status_code == 409
    galileo.runtime.advance(0.5)
    assert galileo.ok("GET", "/system/galileo_status")["loopStatus"] == 1
    assert galileo.advance_until(
        lambda: galileo.ok("GET", "/navigation/loop_task")["loop_count"] >= 1, 180.0)
    assert galileo.ok("GET", "/navigation/loop_task")["state"] == "WORKING"
    stopped = galileo.ok("DELETE", "/navigation/loop_task")
    assert stopped["id"] == task["id"] and stopped["state"] == "CANCELLED"
    galileo.runtime.advance(0.5)
    assert galileo.ok("GET", "/system/galileo_status")["loopStatus"] == 0
    assert galileo.ok("DELETE", "/navigation/loop_task") is None
    for bad in ({}, {"wait_time": "long"}, {"wait_time": -1}):
        assert galileo.post("/navigation/loop_task", bad).status_code == 400
