"""The API around the real RobotRuntime in-process: WebSocket stream and the teleop dead-man."""

from __future__ import annotations

import json
import math
import statistics
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest
from websockets.sync.client import connect

from polynav.api import ApiConfig, create_app
from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds import load_world
from tests.api.server import ServerThread


@pytest.fixture
def runtime(tmp_path: Path) -> Iterator[RobotRuntime]:
    world = load_world("demo")
    store = SiteStore.open(tmp_path / "data", seed_world=world)
    # A modest pace: the WebSocket sender shares the GIL with the simulation thread, and at a high
    # pace a few milliseconds of scheduling delay become a large delay in simulated time.
    robot = RobotRuntime.simulated(store, world, config=RuntimeConfig(speed=4.0, people=False))
    yield robot
    robot.stop()
    store.close()


@pytest.fixture
def server(runtime: RobotRuntime) -> Iterator[ServerThread]:
    thread = ServerThread(create_app(runtime, ApiConfig(port=0))).start()
    yield thread
    thread.stop()


def test_websocket_streams_status_at_the_rate_on_sim_time_and_navigation_events_in_order(
    runtime: RobotRuntime, server: ServerThread
) -> None:
    runtime.start()
    statuses: list[dict[str, Any]] = []
    kinds: list[str] = []
    with connect(f"ws://127.0.0.1:{server.port}/api/ws?rate=5") as ws, \
            httpx.Client(base_url=server.url) as http:
        assert http.post("/api/navigation/start", json={"map": "floor1"}).status_code == 200
        assert http.post("/api/navigation/goal", json={"point": "lobby"}).status_code == 202
        while "navigation_succeeded" not in kinds and "navigation_failed" not in kinds:
            message = json.loads(ws.recv(timeout=30.0))
            if message["type"] == "status":
                statuses.append(message["data"])
            else:
                assert message["type"] == "event"
                kinds.append(message["data"]["kind"])
    nav = [k for k in kinds if k.startswith("navigation_")]
    assert nav == ["navigation_started", "navigation_succeeded"]
    assert kinds.index("mode_changed") < kinds.index("navigation_started")
    stamps = [s["stamp"] for s in statuses]
    assert len(stamps) >= 20
    gaps = [b - a for a, b in zip(stamps, stamps[1:], strict=False)]
    # The snapshot is refreshed every 0.1 s of sim time: a message may come late when the machine
    # is busy (then the next one is not sent early to make up), never early; most come on time.
    assert all(g >= 0.099 for g in gaps), gaps
    assert statistics.median(gaps) == pytest.approx(0.2, abs=0.011), gaps
    rate = (len(stamps) - 1) / (stamps[-1] - stamps[0])
    assert 4.5 <= rate <= 5.5
    assert statuses[-1]["navigation"]["state"] in ("running", "succeeded")


def test_websocket_rejects_an_out_of_range_rate(server: ServerThread) -> None:
    with connect(f"ws://127.0.0.1:{server.port}/api/ws?rate=0") as ws:
        assert json.loads(ws.recv(timeout=5.0))["error"]["code"] == "validation_error"


def test_teleop_then_silence_stops_the_base_within_the_dead_man_timeout(
    runtime: RobotRuntime, server: ServerThread
) -> None:
    with httpx.Client(base_url=server.url) as http:
        assert http.post("/api/teleop", json={"linear": 0.5, "angular": 0.0}).status_code == 200
        runtime.advance(0.4)
        moving = http.get("/api/status").json()["velocity"]["linear"]
        assert moving > 0.2
        # Silence: after 0.5 s without a command the base brakes from at most 0.5 m/s.
        t0 = http.get("/api/status").json()["stamp"]
        stopped = runtime.advance_until(lambda: runtime.status().linear == 0.0, timeout=2.0)
        assert stopped
        status = http.get("/api/status").json()
        assert status["velocity"] == {"linear": 0.0, "angular": 0.0}
        assert status["stamp"] - (t0 - 0.4) <= 0.5 + 0.5
        assert math.isfinite(status["pose"]["x"])


BAD_REQUESTS: list[tuple[str, str, object, int]] = [
    ("POST", "/api/navigation/goal", {"point": "lobby"}, 409),  # not navigating
    ("POST", "/api/navigation/initial_pose", {"x": 1.0, "y": 1.0}, 409),
    ("POST", "/api/navigation/cancel", None, 409),
    ("POST", "/api/navigation/pause", None, 409),
    ("POST", "/api/navigation/resume", None, 409),
    ("POST", "/api/navigation/start", {"map": "nowhere"}, 404),
    ("POST", "/api/navigation/start", {"map": "floor1", "point": "nowhere"}, 404),
    ("POST", "/api/navigation/start", {"map": 7}, 422),
    ("POST", "/api/navigation/goal", b"{", 400),
    ("POST", "/api/teleop", {"linear": [1]}, 422),
    ("POST", "/api/estop", {}, 422),
    ("POST", "/api/local_move", {"rotate": 100.0}, 422),
    ("POST", "/api/local_move", {"distance": "far"}, 422),
    ("PUT", "/api/settings", {"max_linear_velocity": 0.0}, 422),
    ("PUT", "/api/settings", {"unknown": 1.0}, 422),
    ("PUT", "/api/settings", b"[", 400),
    ("GET", "/api/maps/nowhere", None, 404),
    ("POST", "/api/points", {"name": "p", "map": "nowhere", "x": 0.0, "y": 0.0}, 404),
    ("DELETE", "/api/points/nowhere", None, 404),
]


@pytest.mark.parametrize(("method", "path", "body", "status"), BAD_REQUESTS)
def test_bad_input_to_the_real_runtime_is_a_4xx_error_body(
    server: ServerThread, method: str, path: str, body: object, status: int
) -> None:
    with httpx.Client(base_url=server.url) as http:
        if isinstance(body, bytes):
            response = http.request(method, path, content=body,
                                    headers={"content-type": "application/json"})
        else:
            response = http.request(method, path, json=body)
    assert response.status_code == status, response.text
    assert set(response.json()["error"]) == {"code", "message"}


def test_local_move_and_estop_on_the_real_runtime(
    runtime: RobotRuntime, server: ServerThread
) -> None:
    with httpx.Client(base_url=server.url) as http:
        before = http.get("/api/status").json()["pose"]
        assert http.post("/api/local_move", json={"rotate": 1.0}).status_code == 200
        runtime.advance(5.0)
        after = http.get("/api/status").json()["pose"]
        assert abs(math.remainder(after["theta"] - before["theta"] - 1.0, math.tau)) < 0.1
        assert http.post("/api/estop", json={"on": True}).status_code == 200
        runtime.advance(0.1)
        assert http.get("/api/status").json()["estop"]["software"] is True
        assert http.post("/api/teleop", json={"linear": 0.3}).status_code == 409


def test_while_mapping_the_websocket_sends_the_live_map(
    runtime: RobotRuntime, server: ServerThread
) -> None:
    import base64
    import io

    from PIL import Image

    runtime.start()
    with connect(f"ws://127.0.0.1:{server.port}/api/ws?rate=2") as ws, \
            httpx.Client(base_url=server.url) as http:
        assert http.post("/api/mapping/start").status_code == 200
        for _ in range(200):
            message = json.loads(ws.recv(timeout=30.0))
            if message["type"] == "map":
                break
        else:
            raise AssertionError("no map message")
        data = message["data"]
        picture = Image.open(io.BytesIO(base64.b64decode(data["png"])))
        assert picture.size == (data["width"], data["height"])
        assert data["resolution"] == pytest.approx(0.05)
        assert http.post("/api/mapping/cancel").status_code == 200
