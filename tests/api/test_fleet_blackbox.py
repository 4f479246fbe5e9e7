"""Acceptance: ``python -m polynav run --robots 2`` as a subprocess, driven only over HTTP.

Each robot has its own native API (``--port 0``: every server on a free port, read from the
banner); both are sent goals at once and both must get there, and ``GET /api/fleet`` on either
lists both.
"""

from __future__ import annotations

import math
import os
import re
import signal
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest

from tests.api.test_blackbox import STARTUP_TIMEOUT, wait_for

GOAL_TIMEOUT = 120.0  # [s wall]: two robots at --speed 20 on a shared machine


class Building:
    """``polynav run --robots 2 --speed 20 --port 0 ...``; each robot's URL from the banner."""

    def __init__(self, data: Path, robots: int = 2) -> None:
        self.proc = subprocess.Popen(
            [sys.executable, "-m", "polynav", "run", "--robots", str(robots), "--speed", "20",
             "--port", "0", "--yunji-port", "0", "--yunji-http-port", "0", "--data", str(data),
             "--no-people"],
            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True,
            env={**os.environ, "PYTHONUNBUFFERED": "1"},
        )
        self.urls = self._read_urls(robots)
        self.http = [httpx.Client(base_url=url, timeout=10.0) for url in self.urls]
        wait_for(lambda: all(self._answers(c) for c in self.http), STARTUP_TIMEOUT,
                 "GET /api/status never answered")

    def _read_urls(self, robots: int) -> list[str]:
        assert self.proc.stdout is not None
        urls: list[str] = []
        for line in self.proc.stdout:  # ends if the process dies
            found = re.search(r"robot\d+ at .*native API (http://127\.0\.0\.1:\d+)/api", line)
            if found:
                urls.append(found.group(1))
                if len(urls) == robots:
                    return urls
        raise AssertionError(f"polynav run exited with {self.proc.wait()} before serving")

    @staticmethod
    def _answers(client: httpx.Client) -> bool:
        try:
            return client.get("/api/status").status_code == 200
        except httpx.TransportError:
            return False

    def status(self, i: int) -> dict[str, Any]:
        response = self.http[i].get("/api/status")
        assert response.status_code == 200
        return dict(response.json())

    def close(self) -> int:
        for client in self.http:
            client.close()
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
        code = self.proc.wait(timeout=30)
        assert self.proc.stdout is not None
        self.proc.stdout.close()
        return code


@pytest.fixture
def building(tmp_path: Path) -> Iterator[Building]:
    process = Building(tmp_path / "data")
    yield process
    assert process.close() == 0


def _send_both(building: Building, goals: list[dict[str, str]]) -> None:
    for client, goal in zip(building.http, goals, strict=True):
        response = client.post("/api/navigation/goal", json=goal)
        assert response.status_code == 202, response.text


def _both_end(building: Building) -> list[dict[str, Any]]:
    wait_for(lambda: all(building.status(i)["navigation"]["state"] in ("succeeded", "failed")
                         for i in range(2)), GOAL_TIMEOUT, "a goal never ended")
    return [building.status(i) for i in range(2)]


def test_two_robots_each_on_its_own_port_both_reach_their_floor1_points(
        building: Building) -> None:
    fleet = building.http[1].get("/api/fleet")
    assert fleet.status_code == 200
    robots = fleet.json()["robots"]
    assert [r["robot_id"] for r in robots] == ["robot1", "robot2"]
    assert [r["ports"]["native"] for r in robots] == [
        int(url.rsplit(":", 1)[1]) for url in building.urls]
    assert all(r["floor"] == "floor1" and r["mode"] == "navigating" for r in robots)
    assert all("yunji" in r["ports"] for r in robots)

    points = {p["name"]: p for p in building.http[0].get(
        "/api/points", params={"map": "floor1"}).json()}
    goals = [{"point": "office_1"}, {"point": "kitchen"}]
    _send_both(building, goals)
    for status, goal in zip(_both_end(building), goals, strict=True):
        assert status["navigation"]["state"] == "succeeded"
        target = points[goal["point"]]
        assert math.hypot(status["pose"]["x"] - target["x"],
                          status["pose"]["y"] - target["y"]) <= 0.1
    # The fleet listing shows both, from either robot, where they now stand.
    listed = {r["robot_id"]: r for r in building.http[0].get("/api/fleet").json()["robots"]}
    wait_for(lambda: all(
        r["navigation_state"] == "succeeded"
        for r in building.http[0].get("/api/fleet").json()["robots"]), 10.0,
        "the fleet listing never caught up")
    listed = {r["robot_id"]: r for r in building.http[0].get("/api/fleet").json()["robots"]}
    assert math.hypot(listed["robot2"]["pose"]["x"] - points["kitchen"]["x"],
                      listed["robot2"]["pose"]["y"] - points["kitchen"]["y"]) <= 0.2


def test_two_robots_sent_to_floor2_points_at_once_both_succeed_on_floor2(
        building: Building) -> None:
    goals = [{"point": "room_201", "map": "floor2"}, {"point": "room_205", "map": "floor2"}]
    _send_both(building, goals)
    route = building.status(0)["navigation"]["route"]
    assert route["goal_map"] == "floor2" and route["legs"][1]["kind"] == "lift"
    points = {p["name"]: p for p in building.http[0].get(
        "/api/points", params={"map": "floor2"}).json()}
    for status, goal in zip(_both_end(building), goals, strict=True):
        assert status["navigation"]["state"] == "succeeded", status["navigation"]
        assert (status["floor"], status["map"]) == ("floor2", "floor2")
        target = points[goal["point"]]
        assert math.hypot(status["pose"]["x"] - target["x"],
                          status["pose"]["y"] - target["y"]) <= 0.1
    lifts = building.http[1].get("/api/lifts").json()["lifts"]
    assert [car["session"] for car in lifts] == ["", ""]


@pytest.mark.parametrize("robots, message", [
    ("0", "must be at least 1"),
    ("9", "free start points"),
])
def test_bad_robot_count_is_a_clear_error_at_start_up(
        tmp_path: Path, robots: str, message: str) -> None:
    done = subprocess.run(
        [sys.executable, "-m", "polynav", "run", "--robots", robots, "--port", "0",
         "--yunji-port", "0", "--yunji-http-port", "0", "--data", str(tmp_path / "data")],
        capture_output=True, text=True, timeout=120,
    )
    assert done.returncode == 2
    assert message in done.stderr and "Traceback" not in done.stderr
