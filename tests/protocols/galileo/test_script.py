"""A Galileo script, black box, as real ones are written: discover the robot by its UDP
announcement on loopback, get a token, start navigation, move to a target point, poll the task
until COMPLETE, check the pose, stop (issue acceptance, "Black box").

Only plain HTTP with a token in the query string: no polynav import drives the robot. The first
test runs in process, simulated time advancing between requests (the runtime's loop thread is
not started, see conftest), so its history is the same on every run; the second runs the same
script against ``python -m polynav run --speed 20`` in a subprocess, as a user would, with wall
time limits as safety nets only. The third sends the script's robot to a target on floor 3:
the robot rides the site's lift on its own, and the script sees nothing but the task.
"""

from __future__ import annotations

import json
import math
import re
import signal
import socket
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest

from polynav.runtime.robot_runtime import RobotRuntime
from tests.protocols.galileo.conftest import Harness, galileo_config, serving

COVERED: dict[str, str] = {}


@pytest.fixture
def listener() -> Iterator[socket.socket]:
    """A UDP socket that hears loopback broadcasts (bound to 127.255.255.255, port 0)."""
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sock.bind(("127.255.255.255", 0))
    sock.settimeout(10.0)
    yield sock
    sock.close()


class Script:
    """What a Galileo client does: HTTP to the announced address with ``?token=``."""

    def __init__(self, g: Harness, base: str, token: str) -> None:
        self.g = g
        self.http = httpx.Client(base_url=base, timeout=20.0)
        self.token = token

    def call(self, path: str, /, **params: Any) -> Any:
        response = self.http.get("/api/v1" + path, params={**params, "token": self.token})
        assert response.status_code == 200, (path, response.text)
        return response.json()

    def wait(self, path: str, done: Any, timeout: float, /, **params: Any) -> Any:
        """Poll ``path`` every 0.2 s of simulated time until ``done(reply)``."""
        reply: dict[str, Any] = {}

        def check() -> bool:
            reply.update(self.call(path, **params))
            return bool(done(reply))

        deadline = self.g.runtime.now() + timeout
        while not check():
            assert self.g.runtime.now() < deadline, reply
            self.g.runtime.advance(0.2)
        return reply


def test_script_discovers_navigates_to_a_target_and_stops(
    runtime: RobotRuntime, listener: socket.socket
) -> None:
    udp_port = listener.getsockname()[1]
    config = galileo_config(announce=True, udp_port=udp_port, require_token=True,
                            announce_interval=0.2)
    with serving(runtime, config) as g:
        data, (address, _) = listener.recvfrom(4096)
        announced = json.loads(data)
        assert list(announced) == ["id", "port", "mac", "version"]
        assert address == "127.0.0.1" and announced["port"] == g.server.port
        base = f"http://{address}:{g.server.port}"
        token = httpx.get(base + "/token", params={"username": "admin", "password": "admin"},
                          timeout=20.0).json()
        assert token["result"] is True
        script = Script(g, base, token["token"])
        try:
            assert script.call("/navigation/stop")["result"] is True  # scripts start clean
            assert script.call("/system/status") == {"status": "Free"}
            assert script.call("/navigation/start", map="floor1", path="default")["result"]
            script.wait("/system/galileo_status", lambda s: s["navStatus"] == 1, 30.0)
            target = g.runtime.store.point("floor1", "corridor_west")
            index = script.call("/navigation/move_to_index", index=11)  # corridor_west
            assert index["sub_tasks"][0]["x"] == target.pose.x
            final = script.wait("/task", lambda t: t["state"] in ("COMPLETE", "ERROR"), 180.0,
                                id=index["id"])
            assert final["state"] == "COMPLETE", final
            pose = script.call("/navigation/pose")
            assert math.hypot(pose["x"] - target.pose.x, pose["y"] - target.pose.y) < 0.1
            heading_error = math.remainder(math.radians(pose["angle"]) - target.pose.theta,
                                           math.tau)
            assert abs(heading_error) < 0.1
            assert script.call("/navigation/stop") == {"result": True, "description": ""}
            script.wait("/system/status", lambda s: s["status"] == "Free", 10.0)
        finally:
            script.http.close()


def test_script_sends_the_robot_to_a_target_on_another_floor(
    runtime: RobotRuntime, listener: socket.socket
) -> None:
    """``move_to_index`` with ``map=floor3`` from floor 1: one task, polled until COMPLETE, the
    robot on floor 3 at the target (the lift ride is the runtime's, as on a Galileo robot)."""
    config = galileo_config(announce=True, udp_port=listener.getsockname()[1],
                            require_token=True, announce_interval=0.2)
    with serving(runtime, config) as g:
        _, (address, _) = listener.recvfrom(4096)
        base = f"http://{address}:{g.server.port}"
        token = httpx.get(base + "/token", params={"username": "admin", "password": "admin"},
                          timeout=20.0).json()
        script = Script(g, base, token["token"])
        try:
            assert script.call("/navigation/start", map="floor1", path="default")["result"]
            script.wait("/system/galileo_status", lambda s: s["navStatus"] == 1, 30.0)
            points = script.call("/navigation/nav_points", map_name="floor3",
                                 path_name="default")["path_data"]
            target = g.runtime.store.point("floor3", "nurse_station").pose
            index = next(i for i in range(len(points.splitlines()))
                         if math.hypot(_target(points, i)[0] - target.x,
                                       _target(points, i)[1] - target.y) < 1e-6)
            task = script.call("/navigation/move_to_index", map="floor3", path="default",
                               index=index)
            final = script.wait("/task", lambda t: t["state"] in ("COMPLETE", "ERROR"), 900.0,
                                id=task["id"])
            assert final["state"] == "COMPLETE", final
            assert g.runtime.status().map == "floor3"
            pose = script.call("/navigation/pose")
            assert math.hypot(pose["x"] - target.x, pose["y"] - target.y) < 0.1, pose
            heading = math.remainder(math.radians(pose["angle"]) - target.theta, math.tau)
            assert abs(heading) < 0.1, pose
            assert script.call("/navigation/stop")["result"] is True
        finally:
            script.http.close()


class RunningPolynav:
    """``python -m polynav run`` in a subprocess, at ``--speed 20``, every port ephemeral, its
    discovery announcements sent to ``udp_port`` on the loopback broadcast address."""

    def __init__(self, data: Path, udp_port: int) -> None:
        data.mkdir(parents=True)
        self.stderr = data.parent / "stderr.txt"  # a file: a full pipe would block the robot
        with self.stderr.open("w") as stderr:
            self.proc = subprocess.Popen(
                [sys.executable, "-m", "polynav", "run", "--data", str(data), "--speed", "20",
                 "--port", "0", "--galileo-port", "0", "--galileo-ws-port", "0",
                 "--galileo-modbus-port", "0", "--galileo-udp-fast-port", "0",
                 "--galileo-udp-port", str(udp_port), "--galileo-require-token", "--no-yunji",
                 "--no-puwei", "--no-people"],
                stdout=subprocess.PIPE, stderr=stderr, text=True,
            )
        self.lines: list[str] = []
        assert self.proc.stdout is not None
        for line in self.proc.stdout:
            self.lines.append(line.rstrip("\n"))
            if "Ctrl-C" in line or len(self.lines) > 20:
                break
        found = [m for line in self.lines
                 if (m := re.search(r"Galileo API http://[\d.]+:(\d+)/api/v1", line))]
        assert len(found) == 1, (self.lines, self.stderr.read_text())
        self.galileo_port = int(found[0].group(1))

    def stop(self) -> None:
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
            try:
                self.proc.communicate(timeout=60)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.communicate()


def _poll(call: Callable[[], Any], done: Callable[[Any], bool], wall_timeout: float,
          pause: float = 0.02) -> Any:
    """Call until ``done(reply)``, as scripts do (a safety limit only: the robot runs at 20x)."""
    deadline = time.monotonic() + wall_timeout
    while True:
        reply = call()
        if done(reply):
            return reply
        assert time.monotonic() < deadline, reply
        time.sleep(pause)


def test_script_against_polynav_run_in_a_subprocess(listener: socket.socket,
                                                     tmp_path: Path) -> None:
    """The same script against ``polynav run`` (a separate process on its own clock): the
    address from the announcement's sender, the token, start, move_to_index, the task polled in
    a tight loop until COMPLETE, the pose within 0.1 m / 0.1 rad, stop."""
    polynav = RunningPolynav(tmp_path / "data", listener.getsockname()[1])
    try:
        data, (address, _) = listener.recvfrom(4096)
        announced = json.loads(data)
        assert list(announced) == ["id", "port", "mac", "version"]
        assert address == "127.0.0.1" and announced["port"] == polynav.galileo_port
        with httpx.Client(base_url=f"http://{address}:{announced['port']}",
                          timeout=20.0) as http:
            token = http.get("/token", params={"username": "admin", "password": "admin"}
                             ).json()
            assert token["result"] is True

            def call(path: str, /, **params: Any) -> Any:
                reply = http.get("/api/v1" + path, params={**params, "token": token["token"]})
                assert reply.status_code == 200, (path, reply.text)
                return reply.json()

            assert call("/navigation/stop")["result"] is True  # the usual first call
            assert call("/system/status") == {"status": "Free"}
            assert call("/navigation/start", map="floor1", path="default")["result"] is True
            _poll(lambda: call("/system/galileo_status"), lambda s: s["navStatus"] == 1, 60.0)
            points = call("/navigation/nav_points", map_name="floor1", path_name="default")
            target = _target(points["path_data"], 11)  # corridor_west
            task = call("/navigation/move_to_index", index=11)
            assert task["state"] == "WORKING"
            polls = [0]

            def poll_task() -> Any:
                polls[0] += 1
                return call("/task", id=task["id"])

            final = _poll(poll_task, lambda t: t["state"] in ("COMPLETE", "ERROR", "CANCELLED"),
                          120.0, pause=0.0)
            assert final["state"] == "COMPLETE", final
            assert polls[0] > 1
            pose = call("/navigation/pose")
            assert math.hypot(pose["x"] - target[0], pose["y"] - target[1]) < 0.1, pose
            heading = math.remainder(math.radians(pose["angle"]) - target[2], math.tau)
            assert abs(heading) < 0.1, pose
            assert call("/navigation/stop") == {"result": True, "description": ""}
            _poll(lambda: call("/system/status"), lambda s: s["status"] == "Free", 30.0)
    finally:
        polynav.stop()
    assert polynav.proc.returncode == 0, polynav.stderr.read_text()


def _target(path_data: str, index: int) -> tuple[float, float, float]:
    """x, y, theta of target ``index`` from ``nav_points`` text (``x y z angle ...`` lines)."""
    fields = path_data.splitlines()[index].split()
    return float(fields[0]), float(fields[1]), float(fields[3])
