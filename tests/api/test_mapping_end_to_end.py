"""Mapping end to end through the native API around the real runtime: start a map, let the
robot explore a two-room world on its own, watch the live map, stop (saves), then navigate on
the new map to the far room. Over real HTTP on 127.0.0.1; the runtime's loop is not threaded,
so the test advances simulated time itself between requests (deterministic for the seed)."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import httpx
import numpy as np
import pytest

from polynav.geometry import Pose2D
from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from tests.api.server import native_client
from tests.helpers.worlds import TWO_ROOMS_START, two_rooms


@pytest.fixture
def runtime(tmp_path: Path) -> Iterator[RobotRuntime]:
    world = two_rooms()
    with SiteStore.open(tmp_path / "data", seed_world=world) as store:
        yield RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False, seed=7))


@pytest.fixture
def http(runtime: RobotRuntime) -> Iterator[httpx.Client]:
    with native_client(runtime, timeout=30.0) as client:
        yield client


def test_start_explore_save_and_navigate_on_the_new_map(
    runtime: RobotRuntime, http: httpx.Client
) -> None:
    events = runtime.bus.subscribe()
    runtime.advance(0.2)
    assert http.post("/api/mapping/start").status_code == 200
    runtime.advance(0.5)
    assert http.post("/api/mapping/explore").status_code == 200
    kinds: list[str] = []

    def finished() -> bool:
        kinds.extend(e.kind for e in events.get_nowait())
        return "exploration_finished" in kinds

    assert runtime.advance_until(finished, 600.0), http.get("/api/status").json()
    status = http.get("/api/status").json()
    assert status["mode"] == "mapping"
    home = Pose2D(status["pose"]["x"], status["pose"]["y"], status["pose"]["theta"])
    assert home.distance_to(TWO_ROOMS_START) <= 0.6  # it came back
    grid = http.get("/api/mapping/map").json()
    data = np.asarray(grid["data"]).reshape(grid["height"], grid["width"])
    free_area = np.count_nonzero(data == 0) * grid["resolution"] ** 2
    assert free_area > 0.8 * 2 * 5.6 * 5.6 - 4 * 0.36  # both rooms, less the pillars
    assert http.get("/api/mapping/map.png").content.startswith(b"\x89PNG")
    stopped = http.post("/api/mapping/stop", json={"name": "explored"})
    assert stopped.status_code == 200, stopped.text
    assert http.get("/api/status").json()["mode"] == "free"
    assert http.post("/api/mapping/stop", json={"name": "explored"}).status_code == 409
    # The new map's frame is the robot's pose when mapping began (the world's, here).
    started = http.post("/api/navigation/start", json={"map": "explored"})
    assert started.status_code == 200, started.text
    runtime.advance(1.0)
    assert http.get("/api/status").json()["localization"]["state"] == "tracking"
    goal = Pose2D(9.5, 3.0, 0.0)
    sent = http.post("/api/navigation/goal", json={"x": goal.x, "y": goal.y, "theta": 0.0})
    assert sent.status_code == 202, sent.text
    assert runtime.advance_until(lambda: runtime.status().navigation_state != "running", 120.0)
    assert http.get("/api/status").json()["navigation"]["state"] == "succeeded"
    assert runtime.simulation.true_pose.distance_to(goal) <= 0.3
    assert runtime.simulation.collisions == []
