"""A WebSocket client that stops reading costs a bounded amount and is closed with a reason;
status messages are coalesced, events are never dropped silently."""

from __future__ import annotations

import base64
import gc
import os
import socket
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import ClassVar

import pytest

from polynav.api import ApiConfig, create_app
from polynav.runtime.events import RuntimeEvent
from tests.api.fakes import FakeRuntime
from tests.api.server import ServerThread
from tests.helpers.wire_fuzz import rss_bytes

QUEUE = 50


@dataclass(frozen=True, slots=True)
class BulkyEvent(RuntimeEvent):
    """An event with a large payload, so unread bytes pile up fast."""

    kind: ClassVar[str] = "bulky"

    payload: str


@pytest.fixture
def server(fake_runtime: FakeRuntime) -> Iterator[ServerThread]:
    thread = ServerThread(create_app(fake_runtime, ApiConfig(port=0, ws_queue_size=QUEUE))).start()
    yield thread
    thread.stop()


def _silent_client(port: int) -> socket.socket:
    """A WebSocket client that completes the handshake and then never reads."""
    sock = socket.create_connection(("127.0.0.1", port))
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
    key = base64.b64encode(os.urandom(16)).decode()
    sock.sendall(
        f"GET /api/ws?rate=50 HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\n"
        f"Connection: Upgrade\r\nSec-WebSocket-Key: {key}\r\nSec-WebSocket-Version: 13\r\n\r\n"
        .encode()
    )
    head = b""
    while b"\r\n\r\n" not in head:
        head += sock.recv(1)
    assert head.startswith(b"HTTP/1.1 101"), head
    return sock


def _until(condition: Callable[[], bool], what: str) -> None:
    deadline = time.monotonic() + 30.0
    while not condition():
        assert time.monotonic() < deadline, f"timed out waiting until {what}"
        time.sleep(0.01)


def test_a_client_that_never_reads_is_closed_and_memory_stays_bounded(
    fake_runtime: FakeRuntime, server: ServerThread
) -> None:
    sock = _silent_client(server.port)
    try:
        _until(lambda: fake_runtime.bus.subscriber_count == 1, "the client subscribed")
        gc.collect()
        before = rss_bytes()
        payload = "x" * 20_000
        for i in range(3000):  # 60 MB of events, unread
            if fake_runtime.bus.subscriber_count == 0:
                break
            fake_runtime.bus.publish(BulkyEvent(stamp=float(i), payload=payload))
            if i % 50 == 0:
                time.sleep(0.001)  # let the server's loop run between bursts
        _until(lambda: fake_runtime.bus.subscriber_count == 0, "the server dropped the client")
        gc.collect()
        assert rss_bytes() - before < 40 * 1024 * 1024
    finally:
        sock.close()


def test_events_queued_before_the_client_reads_all_arrive_in_order(
    fake_runtime: FakeRuntime, server: ServerThread
) -> None:
    from websockets.sync.client import connect

    with connect(f"ws://127.0.0.1:{server.port}/api/ws?rate=50") as ws:
        _until(lambda: fake_runtime.bus.subscriber_count == 1, "the client subscribed")
        for i in range(QUEUE // 2):
            fake_runtime.bus.publish(BulkyEvent(stamp=float(i), payload=str(i)))
        seen: list[str] = []
        while len(seen) < QUEUE // 2:
            message = ws.recv(timeout=10.0)
            assert isinstance(message, str)
            if '"type":"event"' in message:
                seen.append(message)
        assert [f'"payload":"{i}"' in m for i, m in enumerate(seen)] == [True] * (QUEUE // 2)
