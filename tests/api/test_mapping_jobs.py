"""Stopping and saving a map as jobs, around the real runtime over real HTTP on 127.0.0.1.

With the runtime's loop thread running (wall time): ``POST /api/mapping/stop`` answers 202 while
the map is still being finished, the robot is ``busy`` and its control loop keeps ticking, a
second stop is refused (409), and the job reaches ``saved`` with the map listed. A failing save:
a taken name is a 409 at once (no job); a disk that cannot be written is a ``failed`` job and
the robot maps on, nothing lost. The dialects' synchronous stop is the same job on the caller's
thread. The WebSocket's status carries the same ``mapping``.
"""

from __future__ import annotations

import json
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest
from websockets.sync.client import connect

from polynav.errors import StorageError
from polynav.maps.map import Map
from polynav.runtime.mapping_session import MappingSession
from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from tests.api.server import native_client
from tests.helpers.worlds import two_rooms


@pytest.fixture
def store(tmp_path: Path) -> Iterator[SiteStore]:
    with SiteStore.open(tmp_path / "data", seed_world=two_rooms()) as site:
        yield site


@pytest.fixture
def runtime(store: SiteStore) -> RobotRuntime:
    return RobotRuntime.simulated(store, two_rooms(),
                                  config=RuntimeConfig(people=False, seed=7, speed=4.0))


@pytest.fixture
def http(runtime: RobotRuntime) -> Iterator[httpx.Client]:
    with native_client(runtime, timeout=30.0) as client:
        yield client


@pytest.fixture
def held(monkeypatch: pytest.MonkeyPatch) -> Iterator[threading.Event]:
    """Holds every session's finish (the slow part: 11-50 s on the demo floor) until set; the
    real finish runs then."""
    release = threading.Event()
    finish = MappingSession.finish

    def finish_when_released(session: MappingSession) -> Map:
        assert release.wait(20.0), "the test never released the finish"
        return finish(session)

    monkeypatch.setattr(MappingSession, "finish", finish_when_released)
    yield release
    release.set()


def _wait(what: Any, timeout: float = 20.0) -> None:
    deadline = time.monotonic() + timeout
    while not what():
        assert time.monotonic() < deadline, "timed out"
        time.sleep(0.02)


def _status(http: httpx.Client) -> dict[str, Any]:
    body: dict[str, Any] = http.get("/api/status").json()
    return body


def test_stop_answers_at_once_and_the_robot_keeps_its_loop_while_it_saves(
    runtime: RobotRuntime, http: httpx.Client, held: threading.Event
) -> None:
    runtime.start()
    try:
        assert http.post("/api/mapping/start").status_code == 200
        _wait(lambda: runtime.status().mapping is not None and runtime.status().mapping.scans > 3)
        before = _status(http)["mapping"]
        began = time.monotonic()
        answer = http.post("/api/mapping/stop", json={"name": "west"})
        assert answer.status_code == 202, answer.text
        assert time.monotonic() - began < 5.0  # not held by the finish
        job = answer.json()
        assert (job["name"], job["kind"], job["state"], job["finished_at"]) == (
            "west", "stop", "saving", None)
        status = _status(http)
        assert status["mode"] == "busy"
        # The session as it was when the stop began, with its job.
        assert status["mapping"]["kind"] == "new" and status["mapping"]["job"] == job
        assert status["mapping"]["scans"] >= before["scans"]
        # The control loop runs on: the snapshot's stamp moves while the finish is held.
        stamp = status["stamp"]
        _wait(lambda: _status(http)["stamp"] > stamp + 0.5)
        second = http.post("/api/mapping/stop", json={"name": "west2"})
        assert second.status_code == 409 and "stopping" in second.json()["error"]["message"]
        assert http.post("/api/mapping/save", json={"name": "w"}).status_code == 409
        assert http.post("/api/mapping/cancel").status_code == 409
        assert http.post("/api/navigation/stop").status_code == 409
        assert http.post("/api/navigation/start", json={"map": "f"}).status_code == 409
        # The WebSocket's status is the same snapshot: the session and its job while busy.
        ws_url = str(http.base_url).replace("http://", "ws://") + "/api/ws?rate=5"
        with connect(ws_url) as ws:
            while (message := json.loads(ws.recv(timeout=20.0)))["type"] != "status":
                pass
        assert message["data"]["mode"] == "busy"
        assert message["data"]["mapping"]["job"] == job
        assert http.post("/api/teleop", json={"linear": 0.2, "angular": 0.0}).status_code == 409
        assert "west" not in [m["name"] for m in http.get("/api/maps").json()]
        held.set()
        _wait(lambda: http.get(f"/api/mapping/jobs/{job['id']}").json()["state"] != "saving")
        done = http.get(f"/api/mapping/jobs/{job['id']}").json()
        assert (done["state"], done["error"]) == ("saved", None)
        assert done["finished_at"] > done["started_at"]
        status = _status(http)
        assert status["mode"] == "free" and status["mapping"] is None
        saved = [m for m in http.get("/api/maps").json() if m["name"] == "west"]
        assert len(saved) == 1 and saved[0]["width"] > 20
    finally:
        runtime.stop()


def test_a_taken_name_is_refused_at_once_and_no_job_begins(
    runtime: RobotRuntime, http: httpx.Client
) -> None:
    assert http.post("/api/mapping/start").status_code == 200
    runtime.advance(0.5)
    for path in ("/api/mapping/stop", "/api/mapping/save"):
        taken = http.post(path, json={"name": "f"})  # the seeded floor's map
        assert taken.status_code == 409 and "exists" in taken.json()["error"]["message"]
    assert http.get("/api/mapping/jobs/1").status_code == 404
    status = _status(http)
    assert status["mode"] == "mapping" and status["mapping"]["job"] is None


def test_a_disk_that_fails_fails_the_job_and_the_robot_maps_on(
    runtime: RobotRuntime, http: httpx.Client, store: SiteStore
) -> None:
    assert http.post("/api/mapping/start").status_code == 200
    runtime.advance(1.0)
    scans = runtime.status().mapping.scans  # type: ignore[union-attr]
    maps_dir = store.data_dir / "maps"
    kept = maps_dir.rename(maps_dir.with_name("maps.kept"))
    maps_dir.write_text("not a directory")  # a real write error, as a full or broken disk
    try:
        answer = http.post("/api/mapping/stop", json={"name": "west"})
        assert answer.status_code == 202
        job_id = answer.json()["id"]
        _wait(lambda: http.get(f"/api/mapping/jobs/{job_id}").json()["state"] != "saving")
        job = http.get(f"/api/mapping/jobs/{job_id}").json()
        assert job["state"] == "failed" and job["error"] and job["finished_at"] is not None
        status = _status(http)
        assert status["mode"] == "mapping" and status["mapping"]["job"] == job
        assert "west" not in [m["name"] for m in http.get("/api/maps").json()]
        runtime.advance(1.0)  # nothing lost: the session goes on taking scans
        assert runtime.status().mapping.scans > scans  # type: ignore[union-attr]
        saved = http.post("/api/mapping/save", json={"name": "draft"})
        assert saved.status_code == 202
        _wait(lambda: http.get(f"/api/mapping/jobs/{saved.json()['id']}").json()["state"]
              == "failed")
        assert _status(http)["mode"] == "mapping"
        # The dialects' synchronous stop: the same job, its error raised, mapping goes on.
        with pytest.raises(StorageError):
            runtime.stop_mapping("west", overwrite=True)
        assert runtime.status().mode == "mapping"
        assert runtime.status().mapping.job.state.value == "failed"  # type: ignore[union-attr]
    finally:
        maps_dir.unlink()
        kept.rename(maps_dir)
    again = http.post("/api/mapping/stop", json={"name": "west"})
    assert again.status_code == 202
    _wait(lambda: http.get(f"/api/mapping/jobs/{again.json()['id']}").json()["state"]
          == "saved")
    assert _status(http)["mode"] == "free"
    assert "west" in [m["name"] for m in http.get("/api/maps").json()]


def test_the_synchronous_stop_is_the_same_job(runtime: RobotRuntime) -> None:
    runtime.start_mapping()
    runtime.advance(1.0)
    record = runtime.stop_mapping("west")
    assert getattr(record, "name", None) == "west"
    assert runtime.status().mode == "free" and runtime.status().mapping is None
    job = runtime.mapping_job("1")
    assert (job.name, job.kind.value, job.state.value) == ("west", "stop", "saved")
    assert runtime.store.map_record("west").width > 20


def test_updating_a_map_shows_it_and_saves_under_its_own_name(
    runtime: RobotRuntime, http: httpx.Client
) -> None:
    runtime.advance(0.2)
    started = http.post("/api/mapping/start", json={"map": "f", "point": "initial"})
    assert started.status_code == 200, started.text
    runtime.advance(1.0)
    mapping = _status(http)["mapping"]
    assert (mapping["kind"], mapping["map"], mapping["exploration"]) == ("update", "f", "off")
    # The saved map's known cells count from the start: both rooms, though one is in view.
    assert mapping["mapped_area_m2"] > 60.0
    answer = http.post("/api/mapping/stop", json={"name": "f"})  # its own name: no overwrite
    assert answer.status_code == 202, answer.text
    _wait(lambda: http.get(f"/api/mapping/jobs/{answer.json()['id']}").json()["state"]
          == "saved")
    assert _status(http)["mode"] == "free"
