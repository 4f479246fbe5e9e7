"""Tasks (puwei-api §8, issue 33 item 4) on the task engine and its schedules."""

from __future__ import annotations

import datetime as dt
from typing import Any

from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds.world import World
from tests.protocols.puwei.conftest import EPOCH, MAP, Harness, envelope, refused, serving

COVERED = {
    "POST /api/task/set": "test_set_mode_0_runs_the_actions_loop_times_now",
    "GET /api/task/run/:name": "test_run_starts_a_stored_task_by_name",
    "GET /api/scheduler/release": "test_release_drops_the_schedules_of_a_maps_tasks",
}


def task(name: str = "t1", mode: int = 0, loop: int = 1, actions: Any = None,
         **fields: Any) -> dict[str, Any]:
    body: dict[str, Any] = {"name": name, "mode": mode, "loop": loop, "minute": None,
                            "hour": None, "opt": None,
                            "actions": actions if actions is not None else [
                                {"type": 4, "value": {"time": 1, "angular": 0}}]}
    body.update(fields)
    return body


def set_ok(puwei: Harness, body: dict[str, Any]) -> dict[str, Any]:
    reply = envelope(puwei.post("/api/task/set", body))
    assert reply["code"] == 0, reply
    data: dict[str, Any] = reply["data"]
    return data


def test_set_mode_0_runs_the_actions_loop_times_now(puwei: Harness) -> None:
    puwei.navigate()
    point = puwei.runtime.store.point(MAP, "kitchen")
    body = task(loop=2, actions=[
        {"type": 1, "value": [{"p1": [point.pose.x, point.pose.y, 0.5]}]},
        {"type": 4, "value": {"time": 1, "angular": 0}},
        {"type": 6, "value": 2},
    ])
    data = set_ok(puwei, body)
    assert data["name"] == "t1" and data["mode"] == 0 and data["schedules"] == []
    made = puwei.runtime.tasks.get(data["id"])
    assert made["owner"] == "puwei" and made["state"] == "WORKING"
    assert puwei.advance_until(
        lambda: puwei.runtime.tasks.get(data["id"])["state"] == "COMPLETE", 240.0, step=1.0)
    pose = puwei.runtime.status().pose
    assert abs(pose.x - point.pose.x) < 0.3 and abs(pose.y - point.pose.y) < 0.3


def test_set_translates_every_action_type_onto_the_engine(puwei: Harness) -> None:
    puwei.navigate()
    body = task(mode=1, hour=[23], minute=[0], actions=[
        {"type": 1, "value": [{"a": [1.0, 2.0, 0.5]}]},
        {"type": 2, "value": True},
        {"type": 2, "value": False},
        {"type": 3, "value": {"reverse": True, "name": "r", "points": [[1, 1, 0], [2, 2, 0]]}},
        {"type": 4, "value": {"time": 4, "angular": 0.5}},
        {"type": 5, "value": ["kitchen"]},
        {"type": 6, "value": 1},
    ])
    data = set_ok(puwei, body)
    spec = puwei.runtime.store.task(data["id"]).spec  # type: ignore[attr-defined]
    assert spec["control_type"] == "loop" and spec["target_loop_count"] == 1
    kinds = [(n["type"], {k: v for k, v in n.items() if k not in ("type", "name")})
             for n in spec["sub_tasks"]]
    assert kinds == [
        ("nav_action", {"x": 1.0, "y": 2.0, "theta": 0.5}),
        ("charge_action", {"point": "charger"}),
        ("none_stop_nav_action", {"x": 2.0, "y": 2.0, "radius": 0.3}),
        ("nav_action", {"x": 1.0, "y": 1.0, "theta": 0.0}),
        ("local_move_action", {"angle": 2.0, "distance": 0.0}),
        ("nav_action", {"point": "kitchen"}),
        ("io_action", {"port": 1, "level": 1}),
    ]
    # Mode 1: once, at the next 23:00 of the robot's calendar.
    assert data["schedules"] == ["2026-01-07T23:00:00"]


def test_set_again_under_a_name_replaces_the_task(puwei: Harness) -> None:
    first = set_ok(puwei, task(mode=2, hour=[10], minute=[0], opt=[1]))
    second = set_ok(puwei, task(mode=3, hour=[10], minute=[0], opt=[1, 31]))
    ids = [t["id"] for t in puwei.runtime.tasks.list(owner="puwei")]
    assert ids == [second["id"]] and first["id"] != second["id"]
    assert [s["mode"] for s in puwei.runtime.tasks.schedules.list()] == ["monthly"]
    assert second["schedules"] == ["2026-01-31T10:00:00"]


def test_run_starts_a_stored_task_by_name(puwei: Harness) -> None:
    set_ok(puwei, task(name="later", mode=2, hour=[10], minute=[0], opt=[0]))
    assert refused(puwei.get("/api/task/run/later"))["code"] == 4  # not navigating
    puwei.navigate()
    data = puwei.ok("/api/task/run/later")
    assert data["name"] == "later"
    assert puwei.runtime.tasks.get(data["id"])["state"] == "WORKING"
    assert refused(puwei.get("/api/task/run/nothing"))["code"] == 3


def test_release_drops_the_schedules_of_a_maps_tasks(puwei: Harness) -> None:
    puwei.navigate()
    set_ok(puwei, task(name="a", mode=2, hour=[10], minute=[0, 30], opt=[1, 2]))
    set_ok(puwei, task(name="b", mode=3, hour=[10], minute=[0], opt=[5]))
    assert len(puwei.runtime.tasks.schedules.list()) == 2
    assert puwei.ok("/api/scheduler/release", map="floor2") == 0
    assert puwei.ok("/api/scheduler/release", map=MAP) == 2
    assert puwei.runtime.tasks.schedules.list() == []
    assert len(puwei.runtime.tasks.list(owner="puwei")) == 2  # the tasks stay
    assert refused(puwei.get("/api/scheduler/release"))["code"] == 2
    assert refused(puwei.get("/api/scheduler/release", map="nowhere"))["code"] == 3


def test_bad_task_bodies_are_refused_and_change_nothing(puwei: Harness) -> None:
    puwei.navigate()
    bad: list[Any] = [
        task(mode=4), task(mode="0"), task(loop=-1), task(loop=1.5), task(name=""),
        task(actions=[]), task(actions=[{"type": 7, "value": 1}]),
        task(actions=[{"type": 1, "value": [{"p": [1, 2]}]}]),
        task(actions=[{"type": 1, "value": [{"p": [1, "x", 0]}]}]),
        task(actions=[{"type": 2, "value": "yes"}]),
        task(actions=[{"type": 2, "value": False}]),
        task(actions=[{"type": 3, "value": {"points": []}}]),
        task(actions=[{"type": 4, "value": {"time": -1, "angular": 0}}]),
        task(actions=[{"type": 4, "value": {"time": 1, "angular": 3}}]),
        task(actions=[{"type": 5, "value": ["no_such_station"]}]),
        task(actions=[{"type": 6, "value": 9}]),
        task(actions=[{"type": 6}]),
        task(mode=1), task(mode=1, hour=[24], minute=[0]), task(mode=1, hour=[1], minute=[60]),
        task(mode=1, hour=[1], minute=[0], opt=[1]),
        task(mode=2, hour=[1], minute=[0], opt=[7]), task(mode=2, hour=[1], minute=[0]),
        task(mode=3, hour=[1], minute=[0], opt=[0]), task(mode=0, hour=[1]),
        [task()], "task",
    ]
    for body in bad:
        reply = refused(puwei.post("/api/task/set", body))
        assert reply["code"] in (2, 3), (body, reply)
    for raw in (b"{", b'{"name": "x", "mode": NaN}', b"\xff"):
        refused(puwei.http.post("/api/task/set", content=raw, headers={
            **puwei.headers(), "content-type": "application/json"}))
    assert puwei.runtime.tasks.list() == [] and puwei.runtime.tasks.schedules.list() == []


def test_immediate_task_needs_navigation(puwei: Harness) -> None:
    assert refused(puwei.post("/api/task/set", task()))["code"] == 4
    assert puwei.runtime.tasks.list() == []


def test_weekly_task_runs_at_its_simulated_time_and_survives_a_restart(
        world: World, store: SiteStore) -> None:
    config = RuntimeConfig(people=False, calendar_epoch=EPOCH)  # Wednesday 09:00
    runtime = RobotRuntime.simulated(store, world, config=config)
    with serving(runtime) as puwei:
        puwei.login()
        puwei.navigate()
        # Wednesday is 3 (Sunday = 0); at 09:01 the robot's calendar.
        data = set_ok(puwei, task(name="weekly", mode=2, loop=0, hour=[9], minute=[1],
                                  opt=[3, 6]))
        assert data["schedules"] == ["2026-01-07T09:01:00"]
        due = dt.datetime(2026, 1, 7, 9, 1)

        def state() -> str:
            return str(runtime.tasks.get(data["id"])["state"])

        puwei.advance_until(lambda: runtime.calendar_now() >= due - dt.timedelta(seconds=1),
                            120.0, step=0.5)
        assert state() == "WAITTING"
        assert puwei.advance_until(lambda: state() == "WORKING", 2.0, step=0.05)
        assert due <= runtime.calendar_now() < due + dt.timedelta(seconds=1)
        schedule = runtime.tasks.schedules.list(data["id"])[0]
        assert schedule["starts"] == 1
        assert schedule["next_fire"] == "2026-01-10T09:01:00"  # Saturday
    # A restart: the task and its schedule come back from the store.
    again = RobotRuntime.simulated(store, world, config=config)
    stored = [t for t in again.tasks.list(owner="puwei") if t["name"] == "weekly"]
    assert len(stored) == 1
    assert [s["next_fire"] for s in again.tasks.schedules.list(stored[0]["id"])] == [
        "2026-01-10T09:01:00"]


def test_set_again_while_it_runs_cancels_and_replaces_it(puwei: Harness) -> None:
    puwei.navigate()
    first = set_ok(puwei, task(name="now", actions=[{"type": 5, "value": ["kitchen"]}]))
    puwei.runtime.advance(0.5)
    assert puwei.runtime.tasks.get(first["id"])["state"] == "WORKING"
    second = set_ok(puwei, task(name="now", actions=[{"type": 5, "value": ["lobby"]}]))
    running = puwei.runtime.tasks.running()
    assert running is not None and running["id"] == second["id"]
    assert [t["id"] for t in puwei.runtime.tasks.list(owner="puwei")] == [second["id"]]
