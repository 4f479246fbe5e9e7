"""A rosbridge server on 127.0.0.1 port 0 over a small test graph, and a raw WebSocket client.

The graph stands for what the dialect mappings declare: a published topic (``/counter``,
latched ``/state``), a topic clients publish on (``/command``, recorded), services that answer,
fail and wait. The server's own tests need nothing of the runtime; the androidmsg and sensor
tests build their graph from a runtime instead.
"""

from __future__ import annotations

import contextlib
import json
import threading
from collections.abc import Iterator
from typing import Any

import pytest
from websockets.sync.client import ClientConnection, connect

from polynav.clock import ManualClock
from polynav.protocols.ros_graph import Graph, Message, RosError, Service, Subscription, Topic
from polynav.protocols.rosbridge import RosbridgeConfig, RosbridgeThread

TIMEOUT = 10.0


class SampleGraph:
    """The graph and what its handlers saw."""

    def __init__(self) -> None:
        self.graph = Graph()
        self.clock = ManualClock(12.5)
        self.commands: list[Message] = []
        self.release = threading.Event()
        g = self.graph
        g.add_topic(Topic("/counter", "std_msgs/Int16"))
        g.add_topic(Topic("/state", "std_msgs/String", latched=True))
        g.add_subscription(Subscription("/command", "std_msgs/String", self._command))
        g.add_service(Service("/add", "test_srvs/Add", self._add))
        g.add_service(Service("/fail", "std_srvs/Trigger", self._fail))
        g.add_service(Service("/slow", "std_srvs/Trigger", self._slow))

    def _command(self, msg: Message) -> None:
        if not isinstance(msg.get("data"), str):
            raise RosError("/command: 'data' must be a string")
        self.commands.append(msg)

    def _add(self, args: Message) -> Message:
        a, b = args.get("a"), args.get("b")
        if not isinstance(a, (int, float)) or not isinstance(b, (int, float)):
            raise RosError("'a' and 'b' must be numbers")
        return {"sum": a + b}

    def _fail(self, args: Message) -> Message:
        raise RosError("this service always fails")

    def _slow(self, args: Message) -> Message:
        self.release.wait(TIMEOUT)
        return {"success": True, "message": "released"}


class Client:
    """A raw rosbridge client: JSON frames out, JSON frames in."""

    def __init__(self, port: int) -> None:
        # websockets >= 17.1 wants a context manager; enter it here, exit in close().
        self.ws: ClientConnection = connect(f"ws://127.0.0.1:{port}", max_size=None,
                                            open_timeout=TIMEOUT).__enter__()

    def send(self, frame: Any) -> None:
        self.ws.send(frame if isinstance(frame, (str, bytes)) else json.dumps(frame))

    def recv(self, timeout: float = TIMEOUT) -> dict[str, Any]:
        frame = self.ws.recv(timeout)
        data = json.loads(frame)
        assert isinstance(data, dict)
        return data

    def recv_op(self, op: str, timeout: float = TIMEOUT, **match: Any) -> dict[str, Any]:
        """The next frame of ``op`` whose fields match (others are skipped)."""
        while True:
            data = self.recv(timeout)
            if data.get("op") == op and all(data.get(k) == v for k, v in match.items()):
                return data

    def call(self, service: str, args: Any = None, ident: str = "c1") -> dict[str, Any]:
        frame: dict[str, Any] = {"op": "call_service", "id": ident, "service": service}
        if args is not None:
            frame["args"] = args
        self.send(frame)
        return self.recv_op("service_response", id=ident)

    def close(self) -> None:
        self.ws.close()


@contextlib.contextmanager
def rosbridge(graph: Graph, clock: Any, **config: Any) -> Iterator[RosbridgeThread]:
    server = RosbridgeThread(graph, clock, RosbridgeConfig(port=0, **config))
    try:
        yield server
    finally:
        server.stop()


@pytest.fixture
def sample() -> SampleGraph:
    return SampleGraph()


@pytest.fixture
def server(sample: SampleGraph) -> Iterator[RosbridgeThread]:
    with rosbridge(sample.graph, sample.clock) as s:
        yield s


@pytest.fixture
def client(server: RosbridgeThread) -> Iterator[Client]:
    c = Client(server.port)
    try:
        yield c
    finally:
        c.close()
