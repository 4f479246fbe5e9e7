"""The Galileo SDK client (``polynav.clients.galileo``) against ``polynav run`` in a subprocess at
``--speed 20``, found by its UDP announcement, as an SDK user's program finds a robot: the
spec's examples step by step (§6.7: list robots, connect blocking and async, read the voltage,
move forward, move to a coordinate V1 and V2 until done, the HTTP bridge), every call of §6.5
with what §6.6 says it sends and when it refuses."""

from __future__ import annotations

import json
import math
import re
import socket
import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest

from polynav.clients.galileo import GALILEO_RETURN_CODE as CODE
from polynav.clients.galileo import GalileoSDK
from polynav.protocols.galileo.native import commands as c
from tests.protocols.galileo.test_script import RunningPolynav

_LIST = "test_list_robots_connect_blocking_and_async_and_lose_the_robot"
_MOVE = "test_navigation_goals_loop_and_speed_as_the_examples_do"
_MORE = "test_mapping_charging_voice_bridge_and_shutdown"
COVERED = {
    "galileo-sdk call Connect": _LIST,
    "galileo-sdk call Connect(targetID,timeout,password)": _LIST,
    "galileo-sdk call GetServersOnline": _LIST,
    "galileo-sdk call GetCurrentServer": _LIST,
    "galileo-sdk call CheckServerOnline": _LIST,
    "galileo-sdk call ServerInfo::getID": _LIST,
    "galileo-sdk call Dispose": _LIST,
    "galileo-sdk topic udp:22002 broadcast": _LIST,
    "galileo-sdk call GetCurrentStatus": _LIST,
    "galileo-sdk call SetCurrentStatusCallback": _LIST,
    "galileo-sdk call StartNav": _MOVE,
    "galileo-sdk call StopNav": _MOVE,
    "galileo-sdk call SetGoal": _MOVE,
    "galileo-sdk call PauseGoal": _MOVE,
    "galileo-sdk call ResumeGoal": _MOVE,
    "galileo-sdk call CancelGoal": _MOVE,
    "galileo-sdk call InsertGoal": _MOVE,
    "galileo-sdk call ResetGoal": _MOVE,
    "galileo-sdk call GetGoalNum": _MOVE,
    "galileo-sdk call MoveTo(x,y,goalNum)": _MOVE,
    "galileo-sdk call MoveTo(x,y,theta)": _MOVE,
    "galileo-sdk call WaitForGoal": _MOVE,
    "galileo-sdk call SetGoalReachedCallback": _MOVE,
    "galileo-sdk call SetSpeed": _MOVE,
    "galileo-sdk call SetAngle": _MOVE,
    "galileo-sdk call StartLoop": _MOVE,
    "galileo-sdk call StopLoop": _MOVE,
    "galileo-sdk call SetLoopWaitTime": _MOVE,
    "galileo-sdk call SendCMD": _MOVE,
    "galileo-sdk call StartMapping": _MORE,
    "galileo-sdk call StopMapping": _MORE,
    "galileo-sdk call SaveMap": _MORE,
    "galileo-sdk call UpdateMap": _MORE,
    "galileo-sdk call StartChargeLocal": _MORE,
    "galileo-sdk call StopChargeLocal": _MORE,
    "galileo-sdk call SaveChargeBasePosition": _MORE,
    "galileo-sdk call StartCharge(x,y)": _MORE,
    "galileo-sdk call StartCharge()": _MORE,
    "galileo-sdk call StopCharge": _MORE,
    "galileo-sdk call SendAudio": _MORE,
    "galileo-sdk call EnableGreeting": _MORE,
    "galileo-sdk call SendGalileoBridgeRequest": _MORE,
    "galileo-sdk call PublishTest": _MORE,
    "galileo-sdk call Shutdown": _MORE,
}

WALL = 60.0  # [s] safety limit on a wait; the robot runs at 20x


class Robot:
    """``polynav run`` announcing to the SDK's discovery port, and the SDK."""

    def __init__(self, tmp_path: Path) -> None:
        self.sdk = GalileoSDK(discovery_port=0, command_gap=0.1)
        self.polynav = RunningPolynav(tmp_path / "data", self.sdk.discovery_port)
        ws = [m for line in self.polynav.lines
              if (m := re.search(r"Galileo WebSocket ws://[\d.]+:(\d+)/", line))]
        assert ws, self.polynav.lines
        self.sdk._ws_port = int(ws[0].group(1))  # the announcement names only the HTTP port

    def status(self) -> dict[str, Any]:
        code, status = self.sdk.GetCurrentStatus()
        assert code is CODE.OK and status is not None
        return status

    def until(self, done: Callable[[dict[str, Any]], bool], seconds: float = WALL) -> None:
        deadline = time.monotonic() + seconds
        while not done(self.status()):
            assert time.monotonic() < deadline, self.status()
            time.sleep(0.05)

    def connect(self) -> None:
        assert self.sdk.Connect("", True, 20000, None, None) is CODE.OK

    def navigate(self) -> None:
        assert self.sdk.StartNav() is CODE.OK
        self.until(lambda s: s["visualStatus"] == 1 and s["navStatus"] == 1)

    def close(self) -> None:
        self.sdk.Dispose()
        self.polynav.stop()


@pytest.fixture
def robot(tmp_path: Path) -> Iterator[Robot]:
    r = Robot(tmp_path)
    try:
        yield r
    finally:
        r.close()


def test_list_robots_connect_blocking_and_async_and_lose_the_robot(robot: Robot) -> None:
    sdk = robot.sdk
    assert sdk.StartNav() is CODE.NOT_CONNECTED  # nothing connected yet
    assert sdk.GetCurrentStatus() == (CODE.NOT_CONNECTED, None)
    deadline = time.monotonic() + WALL
    while not sdk.GetServersOnline():  # example 1: list the robots in the LAN
        assert time.monotonic() < deadline
        time.sleep(0.1)
    (server,) = sdk.GetServersOnline()
    assert re.fullmatch(r"[0-9A-F]{76}", server.getID()) and server.ip == "127.0.0.1"
    assert server.port == robot.polynav.galileo_port
    assert sdk.CheckServerOnline(server.getID()) and not sdk.CheckServerOnline("nobody")
    # the IoT form (v1, across LANs through the vendor's relay): none here
    assert sdk.Connect(server.getID(), 10000, "xiaoqiang", None, None) is CODE.NETWORK_ERROR
    assert sdk.Connect("not-a-robot", False, 300, None, None) is CODE.TIMEOUT
    # example 3, async: returns at once, the callback says how it went
    connected: list[tuple[CODE, str]] = []
    lost: list[tuple[CODE, str]] = []
    done = threading.Event()

    def on_connect(code: CODE, robot_id: str) -> None:
        connected.append((code, robot_id))
        done.set()

    statuses: list[dict[str, Any]] = []
    sdk.SetCurrentStatusCallback(lambda code, status: statuses.append(status))
    assert sdk.Connect("", True, 20000, on_connect,
                       lambda code, robot_id: lost.append((code, robot_id))) is CODE.OK
    assert done.wait(WALL) and connected == [(CODE.OK, server.getID())]
    assert sdk.Connect("", True, 1000, None, None) is CODE.ALREADY_CONNECTED
    current = sdk.GetCurrentServer()
    assert current is not None and current.getID() == server.getID()
    # example 5: the voltage, and the status stream (10 Hz)
    time.sleep(0.5)
    assert robot.status()["power"] > 10.0 and len(statuses) >= 3
    assert sdk.PauseGoal() is CODE.INVALIDE_STATE  # not navigating
    # the robot goes away: OnDisconnect, then calls answer NOT_CONNECTED once disposed
    robot.polynav.stop()
    deadline = time.monotonic() + WALL
    while not lost:
        assert time.monotonic() < deadline
        time.sleep(0.05)
    assert lost[0] == (CODE.NOT_CONNECTED, server.getID())
    sdk.Dispose()
    assert sdk.GetCurrentServer() is None and sdk.StopNav() is CODE.NOT_CONNECTED


def test_connect_finds_no_robot_or_too_many() -> None:
    sdk = GalileoSDK(discovery_port=0)
    try:
        assert sdk.Connect("", True, 300, None, None) is CODE.NO_SERVER_FOUND
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sock:
            for n in (1, 2):  # two robots announce themselves
                doc = {"id": f"{n:076X}", "port": 9, "mac": f"02:00:00:00:00:0{n}",
                       "version": "5.0.0"}
                sock.sendto(json.dumps(doc).encode(), ("127.0.0.1", sdk.discovery_port))
            sock.sendto(b"not json", ("127.0.0.1", sdk.discovery_port))
        deadline = time.monotonic() + 10
        while len(sdk.GetServersOnline()) < 2:
            assert time.monotonic() < deadline
            time.sleep(0.02)
        assert sdk.Connect("", True, 1000, None, None) is CODE.MULTI_SERVER_FOUND
        # a robot whose HTTP API is not there
        assert sdk.Connect(f"{1:076X}", False, 1000, None, None) is CODE.NETWORK_ERROR
    finally:
        sdk.Dispose()


def test_navigation_goals_loop_and_speed_as_the_examples_do(robot: Robot) -> None:
    sdk = robot.sdk
    robot.connect()
    assert sdk.StopNav() is CODE.INVALIDE_STATE and sdk.SetGoal(1) is CODE.INVALIDE_STATE
    # example 6: move forward at 0.1 m/s (the dead-man wants it repeated, as teleop does)
    start = robot.status()["currentPosX"]
    for _ in range(10):
        assert sdk.SetSpeed(0.3, 0.0) is CODE.OK
        time.sleep(0.03)
    robot.until(lambda s: s["currentSpeedX"] > 0.05)
    robot.until(lambda s: abs(s["currentSpeedX"]) < 0.01)  # stopped when they stop coming
    assert robot.status()["currentPosX"] != start
    assert sdk.SetSpeed(math.nan, 0.0) is CODE.INVALIDE_PARAMS
    # example 7: start navigation, wait for tracking, move to a coordinate (V1), wait
    robot.navigate()
    assert sdk.StartNav() is CODE.INVALIDE_STATE  # already navigating
    code, count = sdk.GetGoalNum()
    assert code is CODE.OK and count >= 15  # floor1's default path
    reached: list[int] = []
    sdk.SetGoalReachedCallback(lambda goal, status: reached.append(goal))
    code, goal = sdk.MoveTo(5.5, 12.0)
    assert code is CODE.OK and goal == count  # inserted after the path's targets
    assert sdk.WaitForGoal(goal) is CODE.OK
    here = robot.status()
    assert math.hypot(here["currentPosX"] - 5.5, here["currentPosY"] - 12.0) < 0.2
    assert goal in reached
    # V2: with the heading
    code, goal = sdk.MoveTo(8.0, 8.5, math.pi / 2)
    assert (code, goal) == (CODE.OK, -2)
    robot.until(lambda s: s["targetStatus"] == 1)
    robot.until(lambda s: s["targetStatus"] == 0)
    here = robot.status()
    assert math.hypot(here["currentPosX"] - 8.0, here["currentPosY"] - 8.5) < 0.2
    assert abs(math.remainder(here["currentAngle"] - math.pi / 2, math.tau)) < 0.15
    # goals by number: pause, resume, cancel
    assert sdk.SetGoal(300) is CODE.INVALIDE_PARAMS
    assert sdk.SetGoal(3) is CODE.OK  # office_1, far
    robot.until(lambda s: s["targetNumID"] == 3 and s["targetStatus"] == 1)
    assert sdk.PauseGoal() is CODE.OK
    robot.until(lambda s: s["targetStatus"] == 2)
    assert sdk.ResumeGoal() is CODE.OK
    robot.until(lambda s: s["targetStatus"] == 1)
    assert sdk.CancelGoal() is CODE.OK
    robot.until(lambda s: s["targetStatus"] == 0)
    assert sdk.WaitForGoal(99) is CODE.INVALIDE_GOAL  # never shows
    # inserted goals and their reset
    assert sdk.ResetGoal() is CODE.OK
    assert sdk.InsertGoal(6.0, 12.0) is CODE.OK and sdk.InsertGoal(7.0, 12.0) is CODE.OK
    assert sdk.GetGoalNum() == (CODE.OK, count + 2)
    assert sdk.InsertGoal(math.inf, 0.0) is CODE.INVALIDE_PARAMS
    assert sdk.ResetGoal() is CODE.OK and sdk.GetGoalNum() == (CODE.OK, count)
    # raw bytes, as SendCMD(cmd, length): g 1
    assert sdk.SendCMD([0x67, 0x01, 0xFF], 2) is CODE.OK
    robot.until(lambda s: s["targetNumID"] == 1)
    assert sdk.WaitForGoal(1) is CODE.OK
    assert sdk.SendCMD(b"") is CODE.INVALIDE_PARAMS
    # the angle command (v1): turn to -90 degrees
    assert sdk.SetAngle(1, 90) is CODE.OK
    robot.until(lambda s: s["angleGoalStatus"] == 1  # the last goal read 1 too: and turned
                and abs(math.remainder(s["currentAngle"] + math.pi / 2, math.tau)) < 0.15)
    assert sdk.SetAngle(2, 90) is CODE.INVALIDE_PARAMS
    # the loop
    assert sdk.SetLoopWaitTime(1) is CODE.OK
    assert sdk.StartLoop() is CODE.OK
    robot.until(lambda s: s["loopStatus"] == 1)
    assert sdk.StopLoop() is CODE.OK
    robot.until(lambda s: s["loopStatus"] == 0)
    assert sdk.StopNav() is CODE.OK
    robot.until(lambda s: s["navStatus"] == 0)


def test_mapping_charging_voice_bridge_and_shutdown(robot: Robot) -> None:
    sdk = robot.sdk
    robot.connect()
    assert sdk.StopMapping() is CODE.INVALIDE_STATE and sdk.SaveMap() is CODE.INVALIDE_STATE
    assert sdk.StartMapping() is CODE.OK
    robot.until(lambda s: s["mapStatus"] == 1)
    assert sdk.StartNav() is CODE.INVALIDE_STATE  # mapping
    assert sdk.SaveMap() is CODE.OK
    assert sdk.StopMapping() is CODE.OK
    robot.until(lambda s: s["mapStatus"] == 0)
    code, reply = sdk.SendGalileoBridgeRequest("get", "/api/v1/navigation/saved_maps")
    assert code is CODE.OK and reply is not None and reply.status_code == 200
    assert "slamdb" in reply.body and len(reply.uuid) == 36
    assert sdk.UpdateMap() is CODE.OK  # on top of the map in use
    robot.until(lambda s: s["mapStatus"] == 1)
    assert sdk.StopMapping() is CODE.OK
    robot.until(lambda s: s["mapStatus"] == 0)
    # example 8, the HTTP bridge; and bad requests. mapStatus is 0 once the stop is taken, but
    # the map is saved after it (the robot Busy meanwhile, E-02): Free follows, as a client
    # polling the bridge sees (on a loaded machine it once read Busy right after mapStatus 0).
    deadline = time.monotonic() + WALL
    while True:
        code, reply = sdk.SendGalileoBridgeRequest("get", "/api/v1/system/status", "", 10000)
        assert code is CODE.OK and reply is not None and reply.status_code == 200
        status = json.loads(reply.body)["status"]
        if status != "Busy" or time.monotonic() > deadline:
            break
        time.sleep(0.05)
    assert status == "Free"
    assert sdk.SendGalileoBridgeRequest("fetch", "/api/v1/x")[0] is CODE.INVALIDE_PARAMS
    assert sdk.SendAudio("你好") is CODE.OK
    assert sdk.EnableGreeting(True) is CODE.OK and sdk.EnableGreeting(False) is CODE.OK
    assert sdk.PublishTest() is CODE.OK
    # charging: V2 (the robot finds its dock), blocking until on it
    robot.navigate()
    assert sdk.StartCharge(timeout=WALL) is CODE.OK
    assert robot.status()["chargeStatus"] in (1, 2)
    assert sdk.SaveChargeBasePosition() is CODE.OK  # where it stands: on the dock
    code, reply = sdk.SendGalileoBridgeRequest("get", "/api/v1/navigation/charge_pose")
    assert code is CODE.OK and reply is not None
    dock = json.loads(reply.body)
    assert math.hypot(dock["x"] - robot.status()["currentPosX"],
                      dock["y"] - robot.status()["currentPosY"]) < 0.05
    assert sdk.StopCharge() is CODE.OK
    # V1: drive to the dock's position first, then dock. The docked pose itself touches the
    # charger's plate (a goal there is refused as occupied): the position given is in front
    # of the dock, where a user stands the robot to save it.
    assert sdk.SetGoal(1) is CODE.OK  # away from the dock
    assert sdk.WaitForGoal(1) is CODE.OK
    theta = dock["theta"]
    assert sdk.StartCharge(dock["x"] - 0.6 * math.cos(theta), dock["y"] - 0.6 * math.sin(theta),
                           timeout=WALL) is CODE.OK
    assert sdk.StopChargeLocal() is CODE.OK
    assert sdk.SetGoal(1) is CODE.OK and sdk.WaitForGoal(1) is CODE.OK
    assert sdk.StartChargeLocal() is CODE.OK
    robot.until(lambda s: s["chargeStatus"] in (3, 4, 1, 2))
    assert sdk.StopChargeLocal() is CODE.OK
    # the host powers off: the status stream ends
    assert sdk.Shutdown() is CODE.OK
    code, reply = sdk.SendGalileoBridgeRequest("get", "/api/v1/system/status")
    assert code is CODE.OK  # still on during the power-off notice
    assert c.shutdown() == b"\xaa\x44"
