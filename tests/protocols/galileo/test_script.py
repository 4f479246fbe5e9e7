"""A Galileo script, black box, as real ones are written: discover the robot by its UDP
announcement on loopback, get a token, start navigation, move to a target point, poll the task
until COMPLETE, check the pose, stop (issue acceptance, "Black box").

Only plain HTTP with a token in the query string: no polynav import drives the robot. Simulated
time advances between requests (the runtime's loop thread is not started, see conftest).
"""

from __future__ import annotations

import json
import math
import socket
from collections.abc import Iterator
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
