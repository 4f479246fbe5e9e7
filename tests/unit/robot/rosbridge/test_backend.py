"""The bridged robot against a stand-alone rosbridge peer written from the protocol: readings
decoded, /cmd_vel published, the robot's clock followed, the peer killed and restarted."""

from __future__ import annotations

import math
import time
from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest

from polynav.errors import ConfigError
from polynav.geometry import Twist
from polynav.robot.rosbridge import BridgeConfig, RosbridgeBackend
from polynav.robot.rosbridge.client import BridgeError
from tests.helpers.rosbridge_peer import RosbridgePeer


def _header(t: float, frame: str) -> dict[str, Any]:
    return {"seq": 0, "stamp": {"secs": int(t), "nsecs": int(round((t % 1) * 1e9))},
            "frame_id": frame}


def odom(t: float, x: float, yaw: float = 0.0, v: float = 0.0) -> dict[str, Any]:
    return {"header": _header(t, "odom"), "child_frame_id": "base_link",
            "pose": {"pose": {"position": {"x": x, "y": 0.5, "z": 0.0},
                              "orientation": {"x": 0.0, "y": 0.0, "z": math.sin(yaw / 2),
                                              "w": math.cos(yaw / 2)}},
                     "covariance": [0.0] * 36},
            "twist": {"twist": {"linear": {"x": v, "y": 0.0, "z": 0.0},
                                "angular": {"x": 0.0, "y": 0.0, "z": 0.1}},
                      "covariance": [0.0] * 36}}


def clock(t: float) -> dict[str, Any]:
    return {"clock": {"secs": int(t), "nsecs": int(round((t % 1) * 1e9))}}


def until(predicate: Any, timeout: float = 10.0) -> bool:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(0.01)
    return False


@pytest.fixture
def peer() -> Iterator[RosbridgePeer]:
    p = RosbridgePeer()
    p.start()
    yield p
    p.close()


@pytest.fixture
def backend(peer: RosbridgePeer) -> Iterator[RosbridgeBackend]:
    b = RosbridgeBackend(BridgeConfig(url=f"ws://127.0.0.1:{peer.port}", clock_grace=0.3,
                                      silence_timeout=1.0, reconnect_min=0.05,
                                      reconnect_max=0.2))
    yield b
    b.close()


def _ready(peer: RosbridgePeer, backend: RosbridgeBackend, *, with_clock: bool) -> None:
    wanted = {"/clock", "/odom", "/scan", "/imu", "/battery_state", "/tf_static"}
    assert peer.wait(lambda: wanted <= set(peer.subscribed) and "/cmd_vel" in peer.advertised)
    assert peer.subscribed["/scan"] == "sensor_msgs/LaserScan"
    if with_clock:
        peer.send("/clock", clock(30.0))
    peer.send("/odom", odom(30.0, 1.0))
    assert backend.wait_ready(5.0)


def test_readings_are_decoded_and_cmd_vel_is_published(peer: RosbridgePeer,
                                                       backend: RosbridgeBackend) -> None:
    _ready(peer, backend, with_clock=True)
    assert backend.clock.follows_robot and backend.clock.now() == pytest.approx(30.0)
    peer.send("/odom", odom(30.5, 2.0, yaw=0.5, v=0.3))
    peer.send("/scan", {"header": _header(30.5, "laser"), "angle_min": -1.0,
                        "angle_max": 1.0, "angle_increment": 1.0, "time_increment": 0.0,
                        "scan_time": 0.1, "range_min": 0.1, "range_max": 10.0,
                        "ranges": [1.5, None, 20.0], "intensities": []})
    peer.send("/imu", {"header": _header(30.5, "imu"), "orientation": {"x": 0, "y": 0,
                       "z": math.sin(0.25), "w": math.cos(0.25)},
                       "angular_velocity": {"x": 0, "y": 0, "z": 0.2},
                       "linear_acceleration": {"x": 0.1, "y": 0, "z": 9.8}})
    peer.send("/battery_state", {"header": _header(30.5, ""), "percentage": 0.42,
                                 "voltage": 25.1, "current": -1.5, "power_supply_status": 1})
    peer.send("/tf_static", {"transforms": [{
        "header": _header(0, "base_link"), "child_frame_id": "laser",
        "transform": {"translation": {"x": 0.12, "y": 0.0, "z": 0.2},
                      "rotation": {"x": 0, "y": 0, "z": 0, "w": 1}}}]})
    robot = backend.robot
    assert until(lambda: robot.read_scan() is not None and robot.read_imu() is not None
                 and abs(robot.read_battery().percent - 42.0) < 1e-6
                 and robot.read_odometry().pose.x == 2.0)
    reading = robot.read_odometry()
    assert reading.stamp == pytest.approx(30.5)
    assert reading.pose.theta == pytest.approx(0.5) and reading.twist.linear == 0.3
    scan = robot.read_scan()
    assert scan is not None
    assert scan.ranges[0] == pytest.approx(1.5) and np.isinf(scan.ranges[1:]).all()
    imu = robot.read_imu()
    assert imu is not None and imu.yaw == pytest.approx(0.5) and imu.angular_velocity == 0.2
    battery = robot.read_battery()
    assert battery.percent == pytest.approx(42.0) and battery.charging
    peer.send("/scan", {"header": _header(30.6, "laser"), "angle_min": 0.0,
                        "angle_increment": 0.5, "range_max": 5.0, "ranges": [1.0]})
    assert until(lambda: (s := robot.read_scan()) is not None and s.sensor_pose.x == 0.12)
    robot.drive(Twist(0.25, -0.1))
    assert peer.wait(lambda: bool(peer.published["/cmd_vel"]))
    assert peer.published["/cmd_vel"][-1] == {"linear": {"x": 0.25, "y": 0.0, "z": 0.0},
                                              "angular": {"x": 0.0, "y": 0.0, "z": -0.1}}


def test_without_a_clock_topic_the_machines_clock_is_used(peer: RosbridgePeer,
                                                          backend: RosbridgeBackend) -> None:
    _ready(peer, backend, with_clock=False)
    assert not backend.clock.follows_robot
    before = backend.clock.now()
    backend.step()
    assert backend.clock.now() - before >= backend.physics_period - 1e-3
    peer.stop()  # away: the machine's clock stands still for the runtime, navigation holds
    assert until(lambda: not backend.connected)
    held = backend.clock.now()
    time.sleep(0.3)
    backend.step()
    assert backend.clock.now() == held
    peer.start()
    assert until(lambda: backend.connected)
    time.sleep(0.1)
    assert held < backend.clock.now() < held + 0.3  # on from where it stood


def test_the_robots_clock_paces_steps_and_never_runs_backwards(
        peer: RosbridgePeer, backend: RosbridgeBackend) -> None:
    _ready(peer, backend, with_clock=True)
    start = time.monotonic()
    backend.step()  # the robot's time does not move: a step returns after a bounded wait
    assert time.monotonic() - start < 0.5
    assert backend.clock.now() == pytest.approx(30.0)
    peer.send("/clock", clock(30.04))
    assert until(lambda: backend.clock.now() >= 30.04)
    peer.send("/clock", clock(2.0))  # the robot's simulator restarted
    peer.send("/clock", clock(2.5))
    assert until(lambda: backend.clock.now() > 30.04 + 0.4)
    assert backend.clock.now() == pytest.approx(30.54, abs=1e-6)


def test_a_dropped_connection_is_made_again_and_commands_meanwhile_are_dropped(
        peer: RosbridgePeer, backend: RosbridgeBackend) -> None:
    _ready(peer, backend, with_clock=True)
    assert backend.connected and backend.client.connects == 1
    peer.stop()
    assert until(lambda: not backend.connected)
    backend.robot.drive(Twist(0.5, 0.0))  # nowhere to go: dropped
    with pytest.raises(BridgeError, match="not connected"):
        backend.client.call("/rosapi/get_time")
    peer.start()  # the same port
    assert until(lambda: backend.connected and backend.client.connects == 2, 10.0)
    assert peer.wait(lambda: "/odom" in peer.subscribed and "/cmd_vel" in peer.advertised)
    assert until(lambda: peer.send("/odom", odom(31.0, 3.0)) == 1)
    assert until(lambda: backend.robot.read_odometry().pose.x == 3.0)
    assert backend.client.call("/rosapi/get_time") == {"time": {"secs": 1, "nsecs": 0}}
    assert not any(m["linear"]["x"] == 0.5 for m in peer.published["/cmd_vel"])


def test_a_silent_peer_is_taken_as_gone(peer: RosbridgePeer, backend: RosbridgeBackend) -> None:
    _ready(peer, backend, with_clock=False)
    assert until(lambda: backend.client.connects >= 2, 5.0)  # 1 s of silence: reconnected


def test_malformed_messages_are_dropped(peer: RosbridgePeer, backend: RosbridgeBackend) -> None:
    _ready(peer, backend, with_clock=False)
    peer.send("/odom", {"pose": "nowhere"})
    peer.send("/scan", {"ranges": []})
    peer.send_raw("{not json")
    peer.send("/odom", odom(0.0, 7.0))
    assert until(lambda: backend.robot.read_odometry().pose.x == 7.0)
    assert backend.robot.read_scan() is None


def test_fragments_from_the_robot_are_put_together(peer: RosbridgePeer,
                                                   backend: RosbridgeBackend) -> None:
    import json
    _ready(peer, backend, with_clock=False)
    text = json.dumps({"op": "publish", "topic": "/odom", "msg": odom(0.0, 9.0)})
    pieces = [text[i:i + 50] for i in range(0, len(text), 50)]
    for n, piece in enumerate(pieces):
        peer.send_raw(json.dumps({"op": "fragment", "id": "f", "data": piece, "num": n,
                                  "total": len(pieces)}))
    assert until(lambda: backend.robot.read_odometry().pose.x == 9.0)


def test_config_from_a_profile_section() -> None:
    config = BridgeConfig.from_mapping({"url": "ws://10.0.0.5:9090", "scan": "/base_scan"})
    assert config.scan == "/base_scan" and config.odom == "/odom"
    with pytest.raises(ConfigError, match="ros.sacn"):
        BridgeConfig.from_mapping({"sacn": "/x"})
    with pytest.raises(ConfigError, match="ros.url"):
        BridgeConfig(url="http://robot")
    with pytest.raises(ConfigError, match="ros.silence_timeout"):
        BridgeConfig(silence_timeout=0.0)


def test_a_robot_profile_carries_its_ros_names() -> None:
    from polynav.robot.profile import ProfileError, parse_profile

    doc = {"name": "base", "footprint": {"radius": 0.2},
           "ros": {"scan": "/front/scan", "cmd_vel": "/base/cmd_vel"}}
    profile = parse_profile(doc)
    assert profile.ros is not None and profile.ros.scan == "/front/scan"
    assert profile.to_document()["ros"]["cmd_vel"] == "/base/cmd_vel"
    with pytest.raises(ProfileError, match="robot.ros.topic"):
        parse_profile({**doc, "ros": {"topic": "/x"}})
