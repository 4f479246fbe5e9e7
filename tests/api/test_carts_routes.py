"""/api/carts over HTTP around the real RobotRuntime: the demo's loads listed, a cart docked
and left (the runtime advanced between requests), and refusals that change nothing: a load
heavier than the robot carries, nothing to dock to, a bad body."""

from __future__ import annotations

import math
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
    robot = RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False, seed=2))
    robot.start_navigation("floor1")
    robot.advance(0.5)
    yield robot
    store.close()


@pytest.fixture
def http(runtime: RobotRuntime) -> Iterator[httpx.Client]:
    with native_client(runtime) as client:
        yield client


def test_lists_the_demo_carts_and_cabin(http: httpx.Client) -> None:
    body = http.get("/api/carts").json()
    carts = {c["name"]: c for c in body["carts"]}
    assert sorted(carts) == ["cabin_1", "cart_1", "cart_2"]
    assert carts["cart_1"] == {"name": "cart_1", "kind": "cart", "floor": "floor1", "x": 3.2,
                               "y": 20.0, "theta": pytest.approx(math.pi / 2), "length": 0.9,
                               "width": 0.7, "mass": 40.0, "carried": False}
    assert carts["cabin_1"]["kind"] == "cabin" and carts["cabin_1"]["floor"] == "floor2"
    assert body["load"] is None and body["action"] is None


def test_a_cart_docked_and_left_over_http(http: httpx.Client, runtime: RobotRuntime) -> None:
    started = http.post("/api/carts/dock", json={"cart": "cart_1"})
    assert started.status_code == 200, started.text
    assert started.json()["action"] == {"action": "dock", "cart": "cart_1", "load": "cart",
                                        "phase": "going", "attempt": 1}
    assert runtime.advance_until(lambda: not runtime.carts.busy, 90.0)
    body = http.get("/api/carts").json()
    assert body["load"] == {"name": "cart_1", "kind": "cart", "mass": 40.0}
    assert {c["name"]: c["carried"] for c in body["carts"]}["cart_1"] is True
    assert http.post("/api/carts/dock", json={"cart": "cart_2"}).status_code == 409
    assert http.post("/api/carts/leave", json={}).status_code == 200
    assert runtime.advance_until(lambda: not runtime.carts.busy, 30.0)
    body = http.get("/api/carts").json()
    assert body["load"] is None and runtime.simulation.load is None


@pytest.mark.parametrize(
    ("body", "status", "words"),
    [
        ({"cart": "cart_2"}, 409, "weighs 55 kg: this robot carries at most 50 kg"),
        ({"point": "lobby"}, 409, "nothing to dock to at point 'lobby'"),
        ({"point": "nowhere"}, 404, "nowhere"),
        ({"cart": "sofa"}, 409, "no cart or cabin 'sofa'"),
        ({}, 409, "exactly one of cart and point"),
        ({"cart": "cart_1", "point": "lobby"}, 409, "exactly one of cart and point"),
        ({"cart": "cart_1", "cabin_id": "X"}, 409, "only a cabin"),
        ({"cart": "cart_1", "speed": 3}, 422, ""),
    ],
)
def test_a_refused_dock_says_why_and_changes_nothing(
        http: httpx.Client, runtime: RobotRuntime, body: dict[str, object], status: int,
        words: str) -> None:
    answer = http.post("/api/carts/dock", json=body)
    assert answer.status_code == status, answer.text
    assert words in answer.text
    assert not runtime.carts.busy and runtime.status().attempt_id is None
    assert http.post("/api/carts/leave", json={}).status_code == 409
