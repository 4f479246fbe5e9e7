"""Acceptance: ``python -m polynav run`` as a subprocess, driven only over HTTP."""

from __future__ import annotations

import math
import os
import re
import signal
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest

STARTUP_TIMEOUT = 60.0  # [s wall]: numba compiles on a cold cache
GOAL_TIMEOUT = 60.0  # [s wall]: at --speed 20 a demo-floor goal takes a few seconds


class PolynavProcess:
    """``polynav run --speed 20 --port 0 --data DIR`` (every server on a free port); the native
    API's port is read from its banner."""

    def __init__(self, data: Path) -> None:
        self.proc = subprocess.Popen(
            [sys.executable, "-m", "polynav", "run", "--speed", "20", "--port", "0",
             "--yunji-port", "0", "--yunji-http-port", "0", "--galileo-port", "0",
             "--galileo-ws-port", "0", "--galileo-modbus-port", "0",
             "--galileo-udp-fast-port", "0", "--galileo-udp-port", "0", "--puwei-port", "0",
             "--puwei-discovery-port", "0", "--data", str(data),
             "--no-people"],
            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True,
            env={**os.environ, "PYTHONUNBUFFERED": "1"},
        )
        self.url = self._read_url()
        self.http = httpx.Client(base_url=self.url, timeout=10.0)
        wait_for(lambda: self._answers(), STARTUP_TIMEOUT, "GET /api/status never answered")

    def _read_url(self) -> str:
        assert self.proc.stdout is not None
        for line in self.proc.stdout:  # ends if the process dies
            found = re.search(r"native API (http://127\.0\.0\.1:\d+)/api", line)
            if found:
                return found.group(1)
        raise AssertionError(f"polynav run exited with {self.proc.wait()} before serving")

    def _answers(self) -> bool:
        try:
            return self.http.get("/api/status").status_code == 200
        except httpx.TransportError:
            return False

    def status(self) -> dict[str, Any]:
        response = self.http.get("/api/status")
        assert response.status_code == 200
        return dict(response.json())

    def close(self, sig: int = signal.SIGTERM) -> int:
        self.http.close()
        if self.proc.poll() is None:
            self.proc.send_signal(sig)
        code = self.proc.wait(timeout=30)
        assert self.proc.stdout is not None
        self.proc.stdout.close()
        return code


def wait_for(condition: Callable[[], bool], timeout: float, message: str) -> None:
    """Poll ``condition`` (the server runs on its own clock) until it holds or ``timeout``."""
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline:
            raise AssertionError(message)
        time.sleep(0.05)


@pytest.fixture
def server(tmp_path: Path) -> Iterator[PolynavProcess]:
    process = PolynavProcess(tmp_path / "data")
    yield process
    process.close()


def _error(response: httpx.Response, status: int) -> None:
    assert response.status_code == status, response.text
    error = response.json()["error"]
    assert isinstance(error["code"], str) and isinstance(error["message"], str)


def test_goal_to_a_point_succeeds_cancel_gives_canceled_and_errors_are_json(
    server: PolynavProcess,
) -> None:
    points = {p["name"]: p for p in server.http.get("/api/points",
                                                    params={"map": "floor1"}).json()}
    target = points["lobby"]
    far = points["office_1"]

    assert server.http.post("/api/navigation/start", json={"map": "floor1"}).status_code == 200
    goal = server.http.post("/api/navigation/goal", json={"point": "lobby"})
    assert goal.status_code == 202
    first_id = goal.json()["id"]
    assert isinstance(first_id, int)
    wait_for(lambda: server.status()["navigation"]["state"] in ("succeeded", "failed"),
             GOAL_TIMEOUT, "the goal never ended")
    status = server.status()
    assert status["navigation"]["state"] == "succeeded"
    pose = status["pose"]
    assert math.hypot(pose["x"] - target["x"], pose["y"] - target["y"]) <= 0.1
    assert abs(math.remainder(pose["theta"] - target["theta"], math.tau)) <= 0.1

    second = server.http.post("/api/navigation/goal", json={"point": far["name"]})
    assert second.status_code == 202
    assert second.json()["id"] != first_id
    start = (pose["x"], pose["y"])
    wait_for(lambda: math.dist(start, (server.status()["pose"]["x"],
                                       server.status()["pose"]["y"])) > 0.5,
             GOAL_TIMEOUT, "the robot never left for the second goal")
    assert server.status()["navigation"]["state"] == "running"
    assert server.http.post("/api/navigation/cancel").status_code == 200
    wait_for(lambda: server.status()["navigation"]["state"] == "canceled", 10.0,
             "cancel never showed in the status")
    _error(server.http.post("/api/navigation/cancel"), 409)

    _error(server.http.post("/api/navigation/goal", json={"point": "atlantis"}), 404)
    _error(server.http.put("/api/settings", json={"max_linear_velocity": 100.0}), 422)
    _error(server.http.post("/api/navigation/goal", json={"x": "east"}), 422)
    _error(server.http.post("/api/navigation/goal", content=b"{",
                            headers={"content-type": "application/json"}), 400)


def test_a_point_survives_sigkill(tmp_path: Path) -> None:
    data = tmp_path / "data"
    first = PolynavProcess(data)
    added = first.http.post("/api/points", json={"name": "survivor", "map": "floor2",
                                                 "x": 3.25, "y": 4.5, "theta": 1.0})
    assert added.status_code == 201
    assert first.close(signal.SIGKILL) == -signal.SIGKILL

    second = PolynavProcess(data)
    try:
        again = second.http.get("/api/points/survivor")
        assert again.status_code == 200
        assert again.json() == added.json()
    finally:
        assert second.close() == 0
