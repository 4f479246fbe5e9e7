"""``/galileo/cmds`` and ``/galileo/status`` (galileo-wire-protocols §2) over the real wires: the
Galileo WebSocket (3547) with a raw client, and the rosbridge server with roslibpy (a third-party
ROS client), each publishing GalileoNativeCmds and reading GalileoStatus; bad messages get each
wire's own error."""

from __future__ import annotations

import base64
import json
import threading
import time
from collections.abc import Iterator
from typing import Any

import pytest
import roslibpy
from websockets.sync.client import connect

from polynav.protocols.galileo.diagnostics import diagnostics
from polynav.protocols.galileo.native import commands as c
from polynav.protocols.galileo.native.ros_message import (
    NATIVE_CMDS_TYPE,
    decode_native_cmds,
    encode_native_cmds,
)
from polynav.protocols.galileo.ros_topics import add_galileo_topics
from polynav.protocols.ros_graph import Graph
from polynav.protocols.rosbridge import RosbridgeConfig, RosbridgeThread
from tests.protocols.galileo.conftest import Harness

COVERED = {
    "galileo-ros topic /galileo/cmds": "test_rosbridge_cmds_and_status_with_roslibpy",
    "galileo-ros topic /galileo/status": "test_rosbridge_cmds_and_status_with_roslibpy",
}



def test_the_message_codec_takes_lists_and_base64_and_refuses_the_rest() -> None:
    message = encode_native_cmds(c.go_to_goal(4), seq=3, stamp=12.25)
    assert message["length"] == 2 and message["data"] == [0x67, 4]
    assert message["header"]["stamp"] == {"secs": 12, "nsecs": 250_000_000}
    assert decode_native_cmds(message) == c.go_to_goal(4)
    as_text = {"length": 2, "data": base64.b64encode(b"m\x00").decode()}  # rosbridge's uint8[]
    assert decode_native_cmds(as_text) == c.start_navigation()
    for bad, why in (([1, 2], "object"), ({"length": 3, "data": [0x6D, 0]}, "does not count"),
                     ({"data": [0x6D, 256]}, "0..255"), ({"data": "%%%"}, "base64"),
                     ({"data": []}, "1..20"), ({"length": "2", "data": [1, 2]}, "unsigned"),
                     ({"length": 2}, "missing")):
        with pytest.raises(ValueError, match=why):
            decode_native_cmds(bad)


def test_websocket_cmds_start_navigation_and_bad_messages_get_an_error(galileo: Harness) -> None:
    url = f"ws://127.0.0.1:{galileo.server.ws_port}/galileo/cmds"
    with connect(url, open_timeout=10) as ws:
        ws.send(json.dumps({"length": 2, "data": [0x6D, 0x05, 0x01]}))  # length does not count
        error = json.loads(ws.recv(timeout=10))
        assert error["status"] == "error" and "does not count" in error["description"]
        assert diagnostics(galileo.server.ctx).snapshot()["ros.bad_message"] == 1
        ws.send(json.dumps({"header": {"seq": 0, "stamp": {"secs": 0, "nsecs": 0},
                                       "frame_id": ""}, "length": 2, "data": [0x6D, 0]}))
        assert galileo.advance_until(lambda: galileo.runtime.status().mode == "navigating",
                                     20.0, step=0.2, pause=0.01)


@pytest.fixture
def bridge(galileo: Harness) -> Iterator[RosbridgeThread]:
    graph = Graph()
    stop = add_galileo_topics(graph, galileo.server.ctx)
    server = RosbridgeThread(graph, galileo.runtime.clock, RosbridgeConfig(port=0))
    try:
        yield server
    finally:
        server.stop()
        stop()


def test_rosbridge_cmds_and_status_with_roslibpy(galileo: Harness,
                                                 bridge: RosbridgeThread) -> None:
    ros = roslibpy.Ros(host="127.0.0.1", port=bridge.port)
    ros.run(timeout=10)
    try:
        statuses: list[dict[str, Any]] = []
        lock = threading.Lock()

        def keep(message: dict[str, Any]) -> None:
            with lock:
                statuses.append(message)

        status = roslibpy.Topic(ros, "/galileo/status", "galileo_msg/GalileoStatus")
        status.subscribe(keep)
        cmds = roslibpy.Topic(ros, "/galileo/cmds", NATIVE_CMDS_TYPE)
        cmds.advertise()
        time.sleep(0.2)
        cmds.publish(roslibpy.Message(encode_native_cmds(c.start_navigation())))

        def newest() -> dict[str, Any]:
            with lock:
                return statuses[-1] if statuses else {}

        assert galileo.advance_until(lambda: newest().get("navStatus") == 1
                      and newest().get("visualStatus") == 1, 30.0, step=0.2, pause=0.01)
        cmds.publish(roslibpy.Message({"length": 2,  # data as base64, as rosbridge sends uint8[]
                                       "data": base64.b64encode(c.go_to_goal(1)).decode()}))
        assert galileo.advance_until(lambda: newest().get("targetNumID") == 1
                      and newest().get("targetStatus") == 1, 10.0, step=0.2, pause=0.01)
        assert galileo.advance_until(lambda: newest().get("targetStatus") == 0, 120.0,
                                     step=0.2, pause=0.01)
        pose = galileo.runtime.simulation.true_pose
        assert abs(pose.x - 5.5) < 0.15 and abs(pose.y - 12.5) < 0.15  # target 1: the lobby
        last = newest()
        assert last["currentPosX"] == pytest.approx(galileo.runtime.status().pose.x, abs=0.1)
        cmds.unadvertise()
        status.unsubscribe()
    finally:
        ros.close()  # not terminate(): Twisted's reactor cannot start again in this process
