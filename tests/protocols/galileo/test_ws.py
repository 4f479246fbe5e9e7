"""The Galileo WebSocket on a real socket: topics as ROS JSON, token refusal, /cmd_vel teleop
(galileo-tasks-bt-ws §8; issue item 7)."""

from __future__ import annotations

import json
import math
import threading
from typing import Any

import pytest
from websockets.exceptions import InvalidStatus
from websockets.sync.client import ClientConnection, connect

from polynav.runtime.robot_runtime import RobotRuntime
from tests.protocols.galileo.conftest import Harness, galileo_config, serving
from tests.protocols.galileo.test_status import FIELDS

COVERED = {
    "GET /galileo/status": "test_status_topic_streams_galileo_status_on_the_runtime_clock",
    "GET /{topicName}": "test_ros_topics_in_ros_json_form",
    "GET /cmd_vel": "test_cmd_vel_publish_drives_the_robot",
    "GET /bw_env_sensors/EnvSensorData": "test_env_sensor_topic_drifts_on_the_runtime_clock",
    "GET /bw_env_sensors/AirSensorData": "test_air_sensor_topic_drifts_on_the_runtime_clock",
}

ENV_FIELDS = ("temperature", "rh", "smoke", "pm1_0", "pm2_5", "pm10", "lel", "noise")
AIR_FIELDS = ("temperature", "rh", "co2", "illuminance")


def _url(g: Harness, topic: str, **query: str) -> str:
    q = "&".join(f"{k}={v}" for k, v in query.items())
    return f"ws://127.0.0.1:{g.server.ws_port}{topic}" + (f"?{q}" if q else "")


def _recv(ws: ClientConnection) -> dict[str, Any]:
    message = json.loads(ws.recv(timeout=20))
    assert isinstance(message, dict)
    return message


def test_status_topic_streams_galileo_status_on_the_runtime_clock(galileo: Harness) -> None:
    with connect(_url(galileo, "/galileo/status")) as ws:
        first = _recv(ws)
        assert list(first) == list(FIELDS)
        galileo.runtime.advance(0.35)
        second = _recv(ws)
        assert second["header"]["seq"] > first["header"]["seq"]
        stamp = second["header"]["stamp"]
        assert stamp["secs"] + stamp["nsecs"] / 1e9 > first["header"]["stamp"]["secs"]
        ws.send("ping")  # a text ping is accepted without error
        galileo.runtime.advance(0.2)
        assert _recv(ws)["header"]["frame_id"] == "map"


def test_ros_topics_in_ros_json_form(galileo: Harness) -> None:
    galileo.ok("GET", "/navigation/start", params={"map": "floor1", "start_index": 1})
    galileo.runtime.advance(2.0)
    with connect(_url(galileo, "/odom")) as ws:
        odom = _recv(ws)
        assert odom["header"]["frame_id"] == "odom" and odom["child_frame_id"] == "base_link"
        q = odom["pose"]["pose"]["orientation"]
        assert math.isclose(q["x"] ** 2 + q["y"] ** 2 + q["z"] ** 2 + q["w"] ** 2, 1.0)
        assert len(odom["pose"]["covariance"]) == 36
        assert set(odom["twist"]["twist"]) == {"linear", "angular"}
    with connect(_url(galileo, "/scan")) as ws:
        scan = _recv(ws)
        n = len(scan["ranges"])
        assert n > 100
        assert math.isclose(scan["angle_max"],
                            scan["angle_min"] + (n - 1) * scan["angle_increment"])
        assert all(r >= 0 for r in scan["ranges"])
    with connect(_url(galileo, "/tracked_pose")) as ws:
        tracked = _recv(ws)
        position = tracked["pose"]["position"]
        assert abs(position["x"] - 5.5) < 0.3 and abs(position["y"] - 12.5) < 0.3
    with connect(_url(galileo, "/map"), max_size=None) as ws:
        grid = _recv(ws)
        info = grid["info"]
        assert (info["width"], info["height"], info["resolution"]) == (820, 500, 0.05)
        assert len(grid["data"]) == 820 * 500 and set(grid["data"]) <= {-1, 0, 100}


def test_unknown_topic_and_bad_token_are_refused_at_the_handshake(runtime: RobotRuntime) -> None:
    with serving(runtime, galileo_config(require_token=True)) as g:
        with pytest.raises(InvalidStatus) as refused:
            connect(_url(g, "/galileo/status"))
        assert refused.value.response.status_code == 401
        with pytest.raises(InvalidStatus) as wrong:
            connect(_url(g, "/galileo/status", token="0" * 32))
        assert wrong.value.response.status_code == 401
        token = g.ok("GET", "/token", params={"username": "admin", "password": "admin"})["token"]
        with pytest.raises(InvalidStatus) as unknown:
            connect(_url(g, "/no/such/topic", token=token))
        assert unknown.value.response.status_code == 404
        with connect(_url(g, "/galileo/status", token=token)) as ws:
            assert "navStatus" in _recv(ws)


def test_cmd_vel_publish_drives_the_robot(galileo: Harness,
                                         monkeypatch: pytest.MonkeyPatch) -> None:
    # The server applies a message on its own thread: wait until each one has reached the
    # runtime before advancing the clock, so the simulated history is the same on every run.
    applied = threading.Semaphore(0)
    teleop = galileo.runtime.teleop

    def counted(linear: float, angular: float) -> None:
        teleop(linear, angular)
        applied.release()

    monkeypatch.setattr(galileo.runtime, "teleop", counted)
    before = galileo.runtime.simulation.true_pose
    with connect(_url(galileo, "/cmd_vel")) as ws:
        twist = {"linear": {"x": 0.0, "y": 0.0, "z": 0.0},
                 "angular": {"x": 0.0, "y": 0.0, "z": 0.5}}
        for _ in range(10):
            ws.send(json.dumps(twist))
            assert applied.acquire(timeout=20)
            galileo.runtime.advance(0.2)
        ws.send('{"linear": {"x": "fast"}, "angular": {}}')
        error = _recv(ws)
        assert error["status"] == "error" and "linear.x" in error["description"]
        ws.send("not json")
        assert _recv(ws)["status"] == "error"
    after = galileo.runtime.simulation.true_pose
    turned = math.remainder(after.theta - before.theta, math.tau)
    assert turned > 0.3
    assert math.hypot(after.x - before.x, after.y - before.y) < 0.05


def _sensor_stream(g: Harness, topic: str, fields: tuple[str, ...]) -> list[dict[str, Any]]:
    """Messages of a sensor topic: on subscribing, then after 1 s and 10 s more of the
    runtime's clock (ten drift steps: polynav/robot/sim/devices/environment.py); each is
    checked for the documented fields and types, and the first against the HTTP view of the
    same topic at the same instant."""
    with connect(_url(g, topic)) as ws:
        first = _recv(ws)
        assert g.ok("GET", "/system/topic", params={"topic_name": topic}) == first
        g.runtime.advance(1.0)
        second = _recv(ws)
        g.runtime.advance(10.0)
        third = _recv(ws)
    for message in (first, second, third):
        assert tuple(message) == fields
        assert all(isinstance(v, float) and v >= 0.0 for v in message.values()), message
    return [first, second, third]


def test_env_sensor_topic_drifts_on_the_runtime_clock(galileo: Harness) -> None:
    first, _, later = _sensor_stream(galileo, "/bw_env_sensors/EnvSensorData", ENV_FIELDS)
    assert 15.0 < first["temperature"] < 35.0 and 0.0 <= first["rh"] <= 100.0
    assert later["pm1_0"] <= later["pm2_5"] <= later["pm10"]
    assert later != first  # the readings drift with time (noise moves within seconds)


def test_air_sensor_topic_drifts_on_the_runtime_clock(galileo: Harness) -> None:
    first, _, later = _sensor_stream(galileo, "/bw_env_sensors/AirSensorData", AIR_FIELDS)
    assert 300.0 < first["co2"] < 1500.0 and first["illuminance"] > 0.0
    assert 0.0 <= first["rh"] <= 100.0
    assert later != first
