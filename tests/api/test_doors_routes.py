"""GET /api/doors and an operator's hand on a door, over HTTP around the real RobotRuntime:
doors listed with their state, held open by hand (the leaf leaves the simulated world), let go,
and an unknown door a clear 404 that changes nothing."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest

from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds import load_world
from tests.api.server import native_client


@pytest.fixture
def runtime(tmp_path: Path) -> Iterator[RobotRuntime]:
    world = load_world("demo")
    store = SiteStore.open(tmp_path / "data", seed_world=world)
    robot = RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False))
    yield robot
    store.close()


@pytest.fixture
def http(runtime: RobotRuntime) -> Iterator[httpx.Client]:
    with native_client(runtime) as client:
        yield client


def _doors(http: httpx.Client) -> dict[str, dict[str, object]]:
    answer = http.get("/api/doors")
    assert answer.status_code == 200
    return {d["name"]: d for d in answer.json()["doors"]}


def test_lists_the_demo_doors_with_their_state(http: httpx.Client) -> None:
    doors = _doors(http)
    assert sorted(doors) == ["fire_door_east", "fire_door_west", "lobby_gate"]
    assert doors["lobby_gate"] == {
        "name": "lobby_gate", "kind": "gate", "floor": "floor1",
        "segment": [10.05, 11.0, 10.05, 13.0], "width": 2.0, "state": "closed",
        "holders": [], "answering": True}
    assert doors["fire_door_west"]["kind"] == "door"
    assert doors["fire_door_west"]["floor"] == "floor2"


def test_an_operator_holds_a_door_open_and_lets_it_go(http: httpx.Client,
                                                      runtime: RobotRuntime) -> None:
    floor = runtime.simulation.scene.floors["floor1"]
    ix, iy = floor.info.world_to_cell(10.05, 12.0)
    assert floor.occupied[iy, ix]  # the closed gate is in the world
    opened = http.post("/api/doors/lobby_gate/open")
    assert opened.status_code == 200
    assert opened.json()["holders"] == ["operator"]
    assert opened.json()["state"] == "opening"
    runtime.advance(2.0)
    assert _doors(http)["lobby_gate"]["state"] == "open"
    assert not floor.occupied[iy, ix]
    closed = http.post("/api/doors/lobby_gate/close")
    assert closed.status_code == 200 and closed.json()["holders"] == []
    runtime.advance(2.0)
    assert _doors(http)["lobby_gate"]["state"] == "closed"
    assert floor.occupied[iy, ix]


def test_an_unknown_door_is_404_and_nothing_changes(http: httpx.Client) -> None:
    before = _doors(http)
    for action in ("open", "close"):
        answer = http.post(f"/api/doors/back_door/{action}")
        assert answer.status_code == 404
        error = answer.json()["error"]
        assert error["code"] == "not_found" and "back_door" in error["message"]
    assert http.get("/api/doors/lobby_gate/open").status_code == 405
    assert _doors(http) == before


def test_the_status_shows_the_door_the_robot_waits_at_and_its_floors_doors(
        http: httpx.Client, runtime: RobotRuntime) -> None:
    """#38 item 1: doors in the status too. On floor1 the status lists the lobby gate and its
    state; on floor2 before a fire door whose controller is silent, that door is the one waited
    at and held (granted, asked open), closed, and the far door is only listed."""
    runtime.advance(0.2)
    doors = http.get("/api/status").json()["doors"]
    assert doors == {"waiting_for": None, "passing": [], "floor": {"lobby_gate": "closed"}}
    assert http.post("/api/doors/lobby_gate/open").status_code == 200
    runtime.advance(0.2)
    assert http.get("/api/status").json()["doors"]["floor"] == {"lobby_gate": "opening"}

    runtime.start_navigation("floor2", point="corridor_west")
    runtime.set_door_answering("fire_door_west", False)
    runtime.go_to(point="corridor_east", map_name="floor2")
    assert runtime.advance_until(lambda: runtime.status().navigation_state == "paused", 60.0)
    runtime.advance(0.2)
    doors = http.get("/api/status").json()["doors"]
    west = {"name": "fire_door_west", "state": "closed"}
    assert doors == {"waiting_for": west, "passing": [west],
                     "floor": {"fire_door_east": "closed", "fire_door_west": "closed"}}
