"""A Puwei script's whole navigation flow, written as real Puwei clients are (puwei-api §11.2):
discovery over UDP on loopback, login, roslaunch status, navigation on a map, the WebSocket,
I_INIT, I_GOAL with two poses and loop 2, then O_PATH, the O_STATUS stream and the task's
O_EVENTs; the robot ends within ``pos_err`` and ``ang_err`` of the last goal."""

from __future__ import annotations

import json
import math
import socket

import httpx
from websockets.sync.client import connect

from polynav.geometry import yaw_to_quaternion
from polynav.runtime.robot_runtime import RobotRuntime
from tests.protocols.puwei.conftest import MAP, puwei_config, serving


def _pose(x: float, y: float, theta: float) -> dict[str, object]:
    qx, qy, qz, qw = yaw_to_quaternion(theta)
    return {"position": {"x": x, "y": y, "z": 0}, "orientation": {"x": qx, "y": qy, "z": qz,
                                                                   "w": qw}}


def test_discover_login_navigate_and_run_two_goals_twice(runtime: RobotRuntime) -> None:
    with serving(runtime, puwei_config(discovery_port=0)) as h:
        # 1. discovery, as the client does: "discovery" to the group, the reply names the port
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as udp:
            udp.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_IF,
                           socket.inet_aton("127.0.0.1"))
            udp.bind(("127.0.0.1", 0))
            udp.settimeout(5.0)
            assert h.server.discovery_port is not None
            udp.sendto(b"discovery", ("224.0.0.1", h.server.discovery_port))
            reply, (address, _) = udp.recvfrom(256)
        word, port = reply.decode().split()
        assert word == "puwei"
        base = f"http://{address}:{port}"
        with httpx.Client(base_url=base, timeout=20.0) as http:
            # 2. login: the token comes back in the authorization header
            login = http.post("/api/user/login", json={"username": "admin", "password": "admin"})
            assert login.json()["code"] == 0
            auth = {"authorization": login.headers["authorization"]}
            # 3. status, then navigation on a map of the list
            assert http.get("/api/roslaunch/status", headers=auth).json()["data"] == 0
            names = [m["name"] for m in http.get("/api/map/list", headers=auth).json()["data"]]
            assert MAP in names
            assert http.get(f"/api/roslaunch/navigation/{MAP}", headers=auth).json()["code"] == 0
            assert h.advance_until(lambda: runtime.status().mode == "navigating", 10.0)
            assert http.get("/api/roslaunch/status", headers=auth).json()["data"] == 2
            pos_err = http.get("/api/param/get/pos_err", headers=auth).json()["data"]
            ang_err = http.get("/api/param/get/ang_err", headers=auth).json()["data"]
        # 4. the WebSocket with the token, I_INIT where the robot stands, I_GOAL loop 2
        url = f"ws://{address}:{port}/api/ws?token={auth['authorization']}"
        frames: list[dict[str, object]] = []
        with connect(url, open_timeout=10, max_size=1 << 24) as ws:
            def pump(sim_seconds: float) -> None:
                """Advance, then read what the server sent until it is quiet for 5 ms (what
                comes later is read by the next pump)."""
                runtime.advance(sim_seconds)
                while True:
                    try:
                        frames.append(json.loads(ws.recv(timeout=0.005)))
                    except TimeoutError:
                        return

            def codes() -> list[int]:
                return [f["data"]["code"] for f in frames  # type: ignore[index]
                        if f["type"] == 1028]

            truth = runtime.simulation.true_pose
            ws.send(json.dumps({"type": 1, "data": _pose(truth.x, truth.y, truth.theta)}))
            for _ in range(50):
                pump(0.1)
            last = (5.0, 6.0, math.pi / 2)
            ws.send(json.dumps({"type": 2, "data": {
                "poses": [_pose(5.5, 12.5, 0.0), _pose(*last)], "loop": 2}}))
            for _ in range(4000):
                pump(0.1)
                if 3 in codes() or 2049 in codes():
                    break
        found = codes()
        assert 1 in found and found.index(10) < found.index(6) < found.index(3), found
        started = next(f for f in frames if f["type"] == 1028 and f["data"]["code"] == 6)
        finished = next(f for f in frames if f["type"] == 1028 and f["data"]["code"] == 3)
        assert started["data"]["msg"] == "开始执行任务"  # type: ignore[index]
        assert finished["data"]["msg"] == "完成任务"  # type: ignore[index]
        assert any(f["type"] == 1025 for f in frames)
        assert sum(1 for f in frames if f["type"] == 1026) > 50
        final = runtime.simulation.true_pose
        assert math.hypot(final.x - last[0], final.y - last[1]) <= pos_err
        assert math.degrees(abs(math.remainder(final.theta - last[2], math.tau))) <= ang_err
