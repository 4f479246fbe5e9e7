"""Mapping end to end through the native API around the real runtime: start a map, let the
robot explore a two-room world on its own, watch the session in the status (frontiers left,
mapped area, targets reached, then done) and the live map, save a draft as a job while it
explores, stop (a job, 202 at once, saved off the loop), then navigate on the new map to the
far room. Over real HTTP on 127.0.0.1; the runtime's loop is not threaded, so the test advances
simulated time itself between requests (deterministic for the seed); the jobs' workers run on
their own threads and are waited for on wall time."""

from __future__ import annotations

import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

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
    started = runtime.now()
    runtime.advance(0.5)
    mapping = http.get("/api/status").json()["mapping"]
    assert (mapping["kind"], mapping["map"], mapping["exploration"]) == ("new", None, "off")
    assert (mapping["frontiers_left"], mapping["targets_reached"], mapping["job"]) == (
        None, 0, None)
    assert mapping["started_at"] == pytest.approx(started) and mapping["scans"] > 0
    assert mapping["mapped_area_m2"] > 4.0  # the first scans see most of the west room
    assert http.post("/api/mapping/explore").status_code == 200
    kinds: list[str] = []
    seen: list[dict[str, Any]] = []
    draft: dict[str, Any] | None = None
    while "exploration_finished" not in kinds:
        assert runtime.now() < 600.0, http.get("/api/status").json()
        runtime.advance(2.0)
        kinds.extend(e.kind for e in events.get_nowait())
        seen.append(http.get("/api/status").json()["mapping"])
        if draft is None and seen[-1]["targets_reached"] >= 1:
            # A save while exploring: a job; mapping and the exploration go on meanwhile.
            answer = http.post("/api/mapping/save", json={"name": "draft"})
            assert answer.status_code == 202 and answer.json()["state"] == "saving"
            draft = answer.json()
    assert draft is not None and _job_done(http, draft["id"])["state"] == "saved"
    assert "draft" in [m["name"] for m in http.get("/api/maps").json()]
    stages = [m["exploration"] for m in seen]
    assert stages[0] == "exploring" and stages[-1] == "done" and "returning" in stages
    assert stages == sorted(stages, key=["exploring", "returning", "done"].index)
    frontiers = [m["frontiers_left"] for m in seen]
    assert len(set(frontiers)) > 2 and frontiers[-1] == 0
    areas = [m["mapped_area_m2"] for m in seen]
    assert areas[-1] > areas[0] + 20.0  # the east room came in
    assert all(b > a - 0.5 for a, b in zip(areas, areas[1:], strict=False))  # a cell may flip
    assert seen[-1]["targets_reached"] >= 2 and seen[-1]["scans"] > seen[0]["scans"]
    assert seen[-1]["job"]["id"] == draft["id"]  # the session's last job
    status = http.get("/api/status").json()
    assert status["mode"] == "mapping"
    home = Pose2D(status["pose"]["x"], status["pose"]["y"], status["pose"]["theta"])
    assert home.distance_to(TWO_ROOMS_START) <= 0.6  # it came back
    grid = http.get("/api/mapping/map").json()
    data = np.asarray(grid["data"]).reshape(grid["height"], grid["width"])
    free_area = np.count_nonzero(data == 0) * grid["resolution"] ** 2
    assert free_area > 0.8 * 2 * 5.6 * 5.6 - 4 * 0.36  # both rooms, less the pillars
    # The area counted as scans came in is the live map's known area, but for drift.
    known = np.count_nonzero(data >= 0) * grid["resolution"] ** 2
    assert status["mapping"]["mapped_area_m2"] == pytest.approx(known, rel=0.1)
    assert http.get("/api/mapping/map.png").content.startswith(b"\x89PNG")
    stopped = http.post("/api/mapping/stop", json={"name": "explored"})
    assert stopped.status_code == 202, stopped.text
    job = _job_done(http, stopped.json()["id"])
    assert (job["name"], job["kind"], job["state"], job["error"]) == (
        "explored", "stop", "saved", None)
    assert job["finished_at"] >= job["started_at"] > started
    assert http.get("/api/status").json()["mode"] == "free"
    assert http.get("/api/status").json()["mapping"] is None
    assert "explored" in [m["name"] for m in http.get("/api/maps").json()]
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


def _job_done(http: httpx.Client, job_id: str) -> dict[str, Any]:
    """The job once it has ended (its worker runs on wall time), within 30 s."""
    deadline = time.monotonic() + 30.0
    while True:
        job: dict[str, Any] = http.get(f"/api/mapping/jobs/{job_id}").json()
        if job["state"] != "saving" or time.monotonic() > deadline:
            return job
        time.sleep(0.02)
