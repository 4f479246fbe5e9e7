"""A real Yunji server on 127.0.0.1 port 0 over a real runtime on the seeded demo site.

Determinism: the runtime's loop thread is NOT started. The server runs on its own event-loop
thread; runtime commands from its handlers then run at once under the runtime's lock, and the
test advances simulated time itself (``runtime.advance``) between socket exchanges, so every
run sees the same simulated history whatever the machine's speed.
"""

from __future__ import annotations

import contextlib
import json
import socket
from collections.abc import Iterator
from typing import Any, TypeVar

import pytest

from polynav.protocols.yunji import YunjiConfig, serve
from polynav.protocols.yunji.server import YunjiServer
from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds.world import World
from tests.helpers.loop_thread import LoopThread

T = TypeVar("T")
SOCKET_TIMEOUT = 20.0


class Client:
    """A blocking Yunji client: sends commands, reads one JSON packet per line."""

    def __init__(self, port: int) -> None:
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=SOCKET_TIMEOUT)
        self.file = self.sock.makefile("rb")
        self.pushed: list[dict[str, Any]] = []  # notifications and callbacks read on the way

    def send(self, data: bytes | str) -> None:
        self.sock.sendall(data.encode() if isinstance(data, str) else data)

    def read(self) -> dict[str, Any]:
        line = self.file.readline()
        assert line.endswith(b"\n"), f"connection ended: {line!r}"
        packet = json.loads(line)
        assert isinstance(packet, dict)
        return packet

    def response(self) -> dict[str, Any]:
        """The next response; notifications and callbacks on the way go to ``pushed``."""
        while True:
            packet = self.read()
            if packet["type"] == "response":
                return packet
            self.pushed.append(packet)

    def push(self, kind: str, topic: str | None = None) -> dict[str, Any]:
        """The next pushed packet of ``kind`` (and ``topic``), kept or read; others are skipped."""
        while True:
            packet = self.pushed.pop(0) if self.pushed else self.read()
            if packet["type"] == kind and (topic is None or packet.get("topic") == topic):
                return packet

    def request(self, command: str) -> dict[str, Any]:
        """Send ``command`` bare (no terminator), as third-party clients do, and read its reply."""
        self.send(command)
        return self.response()

    def close(self) -> None:
        self.file.close()
        self.sock.close()


class Harness:
    def __init__(self, runtime: RobotRuntime, server: YunjiServer, loop: LoopThread) -> None:
        self.runtime = runtime
        self.server = server
        self.loop = loop
        self.clients: list[Client] = []

    def client(self) -> Client:
        c = Client(self.server.port)
        self.clients.append(c)
        return c


@pytest.fixture
def runtime(world: World, store: SiteStore) -> RobotRuntime:
    return RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False))


@contextlib.contextmanager
def serving(runtime: RobotRuntime, config: YunjiConfig | None = None) -> Iterator[Harness]:
    """A Yunji server for ``runtime`` on its own loop thread (port 0 unless ``config`` says),
    the runtime advanced out of BUSY; clients, server and loop closed at the end."""
    loop = LoopThread()
    server = loop.run(serve(runtime, config or YunjiConfig(port=0)))
    runtime.advance(0.5)  # out of BUSY: navigating and localized on floor1
    h = Harness(runtime, server, loop)
    try:
        yield h
    finally:
        for c in h.clients:
            c.close()
        loop.run(server.close())
        loop.close()


@pytest.fixture
def harness(runtime: RobotRuntime) -> Iterator[Harness]:
    with serving(runtime) as h:
        yield h


@pytest.fixture
def client(harness: Harness) -> Client:
    return harness.client()
