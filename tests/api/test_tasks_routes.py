"""/api/tasks and /api/schedules over real HTTP (the real task commands on the fake robot),
and task events on the native WebSocket."""

from __future__ import annotations

import json
from typing import cast

import httpx
from websockets.sync.client import connect

from polynav.api import ApiConfig, create_app
from polynav.runtime.robot_runtime import RobotRuntime
from tests.api.fakes import FakeRuntime
from tests.api.server import ServerThread

TREE = {"name": "nap", "sub_tasks": [{"type": "sleep_action", "wait_time": 5.0}],
        "blackboard": {"who": "ada"}}


def _error(response: httpx.Response, status: int) -> str:
    assert response.status_code == status, response.text
    return str(response.json()["error"]["message"])


def test_task_life_cycle(client: httpx.Client, fake_runtime: FakeRuntime) -> None:
    made = client.post("/api/tasks", json=TREE)
    assert made.status_code == 201, made.text
    task = made.json()
    assert (task["state"], task["owner"], task["blackboard"]) == ("WAITTING", "native",
                                                                  {"who": "ada"})
    assert [t["id"] for t in client.get("/api/tasks").json()] == [task["id"]]
    assert fake_runtime.store.task(task["id"]).spec == TREE
    started = client.post(f"/api/tasks/{task['id']}/start").json()
    assert started["state"] == "WORKING"
    assert fake_runtime.store.task(task["id"]).state == "WORKING"
    assert "already" in _error(client.post(f"/api/tasks/{task['id']}/start"), 409)
    assert client.post(f"/api/tasks/{task['id']}/pause").json()["state"] == "PAUSED"
    assert _error(client.put(f"/api/tasks/{task['id']}", json=TREE), 409)
    assert client.post(f"/api/tasks/{task['id']}/resume").json()["state"] == "WORKING"
    assert client.post(f"/api/tasks/{task['id']}/trigger").json() == {"released": 0}
    assert client.post(f"/api/tasks/{task['id']}/cancel").json()["state"] == "CANCELLED"
    looped = client.put(f"/api/tasks/{task['id']}/loop", json={"loop": True})
    assert looped.status_code == 200, looped.text
    assert fake_runtime.store.task(task["id"]).spec["loop_flag"] is True
    renamed = client.put(f"/api/tasks/{task['id']}", json=TREE | {"name": "nap2"})
    assert renamed.json()["name"] == "nap2"
    assert client.delete(f"/api/tasks/{task['id']}").status_code == 204
    _error(client.get(f"/api/tasks/{task['id']}"), 404)
    assert fake_runtime.store.tasks() == []


def test_a_bad_tree_is_refused_naming_the_node_and_nothing_is_made(
        client: httpx.Client, fake_runtime: FakeRuntime) -> None:
    message = _error(client.post("/api/tasks", json={
        "name": "x", "sub_tasks": [{"type": "teleport_action"}]}), 409)
    assert "sub_tasks[0]" in message and "teleport_action" in message
    _error(client.post("/api/tasks", json={"name": "x"}), 422)
    assert client.get("/api/tasks").json() == [] and fake_runtime.store.tasks() == []


def test_schedule_crud_and_bad_schedules(client: httpx.Client) -> None:
    task = client.post("/api/tasks", json=TREE).json()
    weekly = {"task_id": task["id"], "mode": "weekly", "weekdays": ["monday"],
              "times": ["10:00"], "loop": 3}
    made = client.post("/api/schedules", json=weekly)
    assert made.status_code == 201, made.text
    schedule = made.json()
    assert (schedule["next_fire"], schedule["starts"]) == ("2030-01-07T10:00:00", 0)
    assert client.get(f"/api/schedules/{schedule['id']}").json() == schedule
    assert client.get("/api/schedules", params={"task_id": task["id"]}).json() == [schedule]
    off = client.put(f"/api/schedules/{schedule['id']}",
                     json={"mode": "monthly", "days": [31], "times": ["08:00"],
                           "enabled": False}).json()
    assert (off["enabled"], off["next_fire"]) == (False, "2030-01-31T08:00:00")
    for bad, words in [({"mode": "once", "at": "2030-01-07T08:00"}, "in the past"),
                       ({"mode": "once", "at": "2030-02-31T08:00"}, "exists"),
                       ({"mode": "monthly", "days": [32], "times": ["08:00"]}, "day 32"),
                       ({"mode": "weekly", "weekdays": ["someday"], "times": ["08:00"]},
                        "unknown weekday"),
                       ({"mode": "weekly", "weekdays": ["mon"], "times": ["08:61"]},
                        "out of range")]:
        assert words in _error(client.post("/api/schedules",
                                           json={"task_id": task["id"], **bad}), 409)
    _error(client.post("/api/schedules", json=weekly | {"task_id": "nope"}), 404)
    assert len(client.get("/api/schedules").json()) == 1
    assert client.delete(f"/api/schedules/{schedule['id']}").status_code == 204
    _error(client.get(f"/api/schedules/{schedule['id']}"), 404)


def test_task_changed_events_reach_the_websocket(fake_runtime: FakeRuntime) -> None:
    server = ServerThread(create_app(cast(RobotRuntime, fake_runtime), ApiConfig(port=0)))
    server.start()
    try:
        with connect(f"ws://127.0.0.1:{server.port}/api/ws") as ws, \
                httpx.Client(base_url=server.url) as http:
            ws.recv(timeout=10.0)  # subscribed once the first message comes
            task = http.post("/api/tasks", json=TREE, params={"start": True}).json()
            seen: list[tuple[str, str, bool]] = []
            while (task["id"], "WORKING", True) not in seen:
                message = json.loads(ws.recv(timeout=10.0))
                if message["type"] == "event" and message["data"]["kind"] == "task_changed":
                    data = message["data"]
                    seen.append((data["task_id"], data["state"], data["root"]))
    finally:
        server.stop()
    assert seen[0] == (task["id"], "WAITTING", True)
