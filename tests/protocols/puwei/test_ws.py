"""The Puwei WebSocket over a real socket (puwei-api §9): every client and server message, the
replay on connect, bad messages, and a client's whole flow from I_INIT to the task's end.

The runtime's loop thread is not started (conftest): the test advances simulated time in small
steps while a client thread collects the frames the server sends.
"""

from __future__ import annotations

import base64
import io
import json
import math
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

import pytest
from PIL import Image
from websockets.exceptions import ConnectionClosed
from websockets.sync.client import ClientConnection, connect

from polynav.geometry import yaw_to_quaternion
from polynav.protocols.puwei.ws import hub
from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds.world import World
from tests.protocols.puwei.conftest import EPOCH, MAP, Harness, serving

COVERED = {
    "GET <unspecified ws path>?token=:token": "test_a_socket_needs_a_token_the_login_gave",
    "ws-in type=0/I_NONE": "test_bad_messages_get_event_1029_and_the_session_goes_on",
    "ws-in type=1/I_INIT": "test_a_client_flow_from_init_to_two_goals_twice",
    "ws-in type=2/I_GOAL": "test_a_client_flow_from_init_to_two_goals_twice",
    "ws-in type=3/I_PAUSE": "test_pause_stops_the_robot_and_resume_goes_on",
    "ws-in type=4/I_CMD": "test_velocity_commands_drive_the_robot_while_they_keep_coming",
    "ws-in type=5/I_CHARGE": "test_charge_docks_onto_the_charger",
    "ws-in type=6/I_CLEAR": "test_clear_and_alarm",
    "ws-in type=7/I_ALARM": "test_clear_and_alarm",
    "ws-in type=8/I_MARKER": "test_markers_are_saved_and_sent_to_every_client",
    "ws-out type=1024/O_MAP": "test_on_connect_the_map_markers_status_and_running_task",
    "ws-out type=1025/O_PATH": "test_a_client_flow_from_init_to_two_goals_twice",
    "ws-out type=1026/O_STATUS": "test_on_connect_the_map_markers_status_and_running_task",
    "ws-out type=1027/O_GOAL": "test_a_client_flow_from_init_to_two_goals_twice",
    "ws-out type=1028/O_EVENT": "test_a_client_flow_from_init_to_two_goals_twice",
    "ws-out type=1029/O_MARKER": "test_markers_are_saved_and_sent_to_every_client",
}


class Client:
    """A WebSocket client whose frames a thread collects."""

    def __init__(self, socket_: ClientConnection) -> None:
        self.socket = socket_
        self.frames: list[dict[str, Any]] = []
        self.closed = threading.Event()
        self._lock = threading.Lock()
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        try:
            for text in self.socket:
                with self._lock:
                    self.frames.append(json.loads(text))
        except ConnectionClosed:
            pass
        self.closed.set()

    def send(self, kind: int, data: Any) -> None:
        self.socket.send(json.dumps({"type": kind, "data": data}))

    def of(self, kind: int) -> list[Any]:
        with self._lock:
            return [f["data"] for f in self.frames if f["type"] == kind]

    def events(self) -> list[int]:
        return [e["code"] for e in self.of(1028)]


@contextmanager
def client(h: Harness, token: str | None = None) -> Iterator[Client]:
    url = f"ws://127.0.0.1:{h.server.port}/api/ws?token={token or h.token}"
    with connect(url, open_timeout=10, max_size=1 << 24) as socket_:
        yield Client(socket_)


def until(h: Harness, done: Callable[[], bool], timeout: float, step: float = 0.1) -> bool:
    """Advance simulated time in ``step`` s steps until ``done()``, giving the server's
    threads a moment of wall time between steps."""
    deadline = h.runtime.now() + timeout
    while not done():
        if h.runtime.now() >= deadline:
            return False
        h.runtime.advance(step)
        time.sleep(0.005)
    return True


def wait_wall(done: Callable[[], bool], seconds: float = 20.0) -> bool:
    deadline = time.monotonic() + seconds
    while not done():
        if time.monotonic() > deadline:
            return False
        time.sleep(0.01)
    return True


def _pose(x: float, y: float, theta: float) -> dict[str, Any]:
    qx, qy, qz, qw = yaw_to_quaternion(theta)
    return {"position": {"x": x, "y": y, "z": 0.0},
            "orientation": {"x": qx, "y": qy, "z": qz, "w": qw}}


def _navigate(h: Harness) -> None:
    h.ok(f"/api/roslaunch/navigation/{MAP}")
    assert until(h, lambda: h.runtime.status().mode == "navigating", 10.0)


def test_a_socket_needs_a_token_the_login_gave(puwei: Harness) -> None:
    url = f"ws://127.0.0.1:{puwei.server.port}/api/ws?token=not-a-token"
    with pytest.raises(Exception) as refused:  # noqa: PT011 - a handshake refusal or close
        with connect(url, open_timeout=10) as socket_:
            socket_.recv(timeout=5)
    assert "1008" in str(refused.value) or "403" in str(refused.value)
    with client(puwei) as c:
        assert wait_wall(lambda: bool(c.of(1026)))


def test_on_connect_the_map_markers_status_and_running_task(puwei: Harness) -> None:
    _navigate(puwei)
    task = puwei.runtime.tasks.create({"name": "wait", "sub_tasks": [
        {"type": "wait_req_action"}]}, start=True)
    with client(puwei) as c:
        assert wait_wall(lambda: bool(c.of(1024) and c.of(1029) and c.of(1026)
                                      and 6 in c.events()))
        grid = c.of(1024)[0]
        record = puwei.runtime.store.map_record(MAP)
        assert (grid["width"], grid["height"]) == (record.width, record.height)
        assert grid["resolution"] == pytest.approx(record.resolution)
        assert grid["origin"] == pytest.approx([record.origin.x, record.origin.y,
                                                record.origin.theta])
        assert grid["data"].startswith("data:image/png;base64,")
        picture = Image.open(io.BytesIO(base64.b64decode(grid["data"].split(",", 1)[1])))
        assert picture.size == (record.width, record.height)
        markers = {name: xyt for item in c.of(1029)[0] for name, xyt in item.items()}
        assert markers["lobby"][:2] == pytest.approx([5.5, 12.5])
        status = c.of(1026)[0]
        for key in ("current", "percentage", "pose", "twist", "voltage", "state", "err", "msg",
                    "time_stamp", "chassis_mode"):
            assert key in status
        assert status["state"] == 1 and status["msg"] == "正在执行任务"
        assert status["time_stamp"] >= int(EPOCH.timestamp() * 1000)
        started = [e for e in c.of(1028) if e["code"] == 6]
        assert started[0]["msg"].startswith("开始执行任务")  # replayed for a late client
        count = len(c.of(1026))
        until(puwei, lambda: False, 2.0)
        assert wait_wall(lambda: len(c.of(1026)) >= count + 5)
        stamps = [s["time_stamp"] for s in c.of(1026)[1:]]
        gaps = [b - a for a, b in zip(stamps, stamps[1:], strict=False)]
        assert gaps and min(gaps) >= 95  # the status rate, 10 Hz of simulated time at most
    puwei.runtime.tasks.cancel(task["id"])


def test_a_client_flow_from_init_to_two_goals_twice(puwei: Harness) -> None:
    rt = puwei.runtime
    _navigate(puwei)
    goals = [(5.5, 12.5, 0.0), (5.0, 6.0, math.pi / 2)]
    with client(puwei) as c, client(puwei) as other:
        truth = rt.simulation.true_pose
        c.send(1, _pose(truth.x, truth.y, truth.theta))
        assert until(puwei, lambda: 2 in c.events() and 1 in c.events(), 10.0)
        c.send(2, {"poses": [_pose(*g) for g in goals], "loop": 2})
        assert wait_wall(lambda: 10 in c.events())
        assert until(puwei, lambda: 3 in c.events() or 2049 in c.events(), 400.0)
        codes = c.events()
        assert codes.index(10) < codes.index(6) < codes.index(13) < codes.index(3)
        assert codes.count(13) == 4  # two goals, twice
        done = [e for e in c.of(1028) if e["code"] == 3]
        assert done[0]["msg"] == "完成任务"
        assert c.of(1025) and c.of(1025)[0]["poses"][0]["pose"]["position"].keys() >= {"x", "y"}
        echoed = other.of(1027)
        assert echoed and echoed[0]["loop"] == 2 and len(echoed[0]["poses"]) == 2
        assert not c.of(1027)  # not echoed to the sender
        # every client hears the task's events (the other socket's reader may lag behind c's)
        assert wait_wall(lambda: 3 in other.events())
        final = rt.simulation.true_pose
        settings = rt.settings()
        assert math.hypot(final.x - 5.0, final.y - 6.0) <= settings.xy_goal_tolerance + 0.02
        assert abs(math.remainder(final.theta - math.pi / 2, math.tau)) <= \
            settings.yaw_goal_tolerance + 0.02


def test_pause_stops_the_robot_and_resume_goes_on(puwei: Harness) -> None:
    rt = puwei.runtime
    _navigate(puwei)
    with client(puwei) as c:
        c.send(2, {"poses": [_pose(29.0, 12.4, 0.0)]})
        assert until(puwei, lambda: rt.status().navigation_state == "running", 10.0)
        until(puwei, lambda: False, 4.0)
        c.send(3, True)
        assert until(puwei, lambda: 5 in c.events(), 5.0)
        until(puwei, lambda: False, 3.0)
        still = rt.simulation.true_pose
        until(puwei, lambda: False, 3.0)
        moved = rt.simulation.true_pose
        assert math.hypot(moved.x - still.x, moved.y - still.y) < 0.02
        c.send(3, False)
        assert until(puwei, lambda: 3 in c.events(), 200.0)
        assert math.hypot(rt.simulation.true_pose.x - 29.0,
                          rt.simulation.true_pose.y - 12.4) < 0.1


def test_velocity_commands_drive_the_robot_while_they_keep_coming(puwei: Harness) -> None:
    rt = puwei.runtime
    _navigate(puwei)
    start = rt.simulation.true_pose
    with client(puwei) as c:
        for _ in range(20):  # 5 Hz of simulated time for 4 s
            c.send(4, {"linear": 0.0, "angular": 0.5})
            time.sleep(0.02)
            rt.advance(0.2)
        turned = abs(math.remainder(rt.simulation.true_pose.theta - start.theta, math.tau))
        assert turned > 0.8
        until(puwei, lambda: False, 2.0)  # no more commands: the dead-man stops it
        before = rt.simulation.true_pose.theta
        until(puwei, lambda: False, 1.0)
        assert abs(rt.simulation.true_pose.theta - before) < 0.01
        c.send(4, {"linear": 1.5, "angular": 0.0})
        assert wait_wall(lambda: 1029 in c.events())


def test_charge_docks_onto_the_charger(puwei: Harness) -> None:
    rt = puwei.runtime
    _navigate(puwei)
    with client(puwei) as c:
        c.send(5, True)
        assert until(puwei, lambda: 11 in c.events(), 200.0)
        assert 7 in c.events() and rt.status().charging
        c.send(5, False)  # nothing to cancel: docked and done
        assert wait_wall(lambda: 2052 in c.events())


def test_clear_and_alarm(puwei: Harness) -> None:
    rt = puwei.runtime
    _navigate(puwei)
    rt.set_software_estop(True)
    with client(puwei) as c:
        c.send(6, None)
        assert wait_wall(lambda: 12 in c.events())
        assert not rt.status().estop_software
        c.send(7, True)
        assert wait_wall(lambda: rt.peripherals.buzzer_on)
        c.send(7, False)
        assert wait_wall(lambda: not rt.peripherals.buzzer_on)


def test_markers_are_saved_and_sent_to_every_client(puwei: Harness) -> None:
    _navigate(puwei)
    with client(puwei) as c, client(puwei) as other:
        assert wait_wall(lambda: bool(other.of(1029)))
        c.send(8, [{"m1": [6.0, 10.0, 90.0]}, {"lobby": [5.6, 12.4, 0.0]}])
        assert wait_wall(lambda: 9 in other.events() and len(other.of(1029)) >= 2)
        point = puwei.runtime.store.point(MAP, "m1")
        assert (point.pose.x, point.pose.y) == (6.0, 10.0)
        assert point.pose.theta == pytest.approx(math.pi / 2)  # degrees on the wire
        latest = {n: v for item in other.of(1029)[-1] for n, v in item.items()}
        assert latest["m1"] == pytest.approx([6.0, 10.0, 90.0])
        assert latest["lobby"][:2] == pytest.approx([5.6, 12.4])
        c.send(8, [{"bad": [1, 2]}])
        assert wait_wall(lambda: 1029 in c.events())


@pytest.mark.parametrize("frame", [
    "not json", json.dumps([1, 2]), json.dumps({"data": None}), json.dumps({"type": 99}),
    json.dumps({"type": 0, "data": None}), json.dumps({"type": "1", "data": {}}),
    json.dumps({"type": 1, "data": {"position": {"x": "a", "y": 0}}}),
    json.dumps({"type": 2, "data": {"poses": []}}),
    json.dumps({"type": 2, "data": {"poses": [_pose(1, 2, 0)], "loop": -1}}),
    json.dumps({"type": 3, "data": "yes"}), json.dumps({"type": 6, "data": 1}),
    json.dumps({"type": 4, "data": {"linear": 0.1}}),
])
def test_bad_messages_get_event_1029_and_the_session_goes_on(puwei: Harness,
                                                            frame: str) -> None:
    with client(puwei) as c:
        c.socket.send(frame)
        assert wait_wall(lambda: 1029 in c.events())
        assert c.of(1028)[-1]["msg"].startswith("输入的命令无效")
        c.send(7, True)
        assert wait_wall(lambda: puwei.runtime.peripherals.buzzer_on)
        assert not c.closed.is_set()


def test_a_goal_before_navigation_is_refused_with_task_failed(puwei: Harness) -> None:
    with client(puwei) as c:
        c.send(2, {"poses": [_pose(5.5, 12.5, 0.0)]})
        assert wait_wall(lambda: 2049 in c.events())
        assert puwei.runtime.tasks.running() is None


def test_closing_the_client_ends_its_session(world: World, store: SiteStore) -> None:
    runtime = RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False,
                                                                         calendar_epoch=EPOCH))
    with serving(runtime) as h:
        h.login()
        with client(h):
            assert wait_wall(lambda: len(hub(h.server.ctx).sessions) == 1)
        assert wait_wall(lambda: not hub(h.server.ctx).sessions)
