"""The Yunji server's transport: slow readers, many clients, the per-request broad except."""

from __future__ import annotations

import asyncio
import socket
from collections.abc import Callable

import pytest

from polynav.errors import Conflict, InvalidRequest, NotFound, PolynavError
from polynav.protocols.yunji import YunjiConfig, context, errors, routes, serve
from polynav.protocols.yunji.messages import Reply, Status
from polynav.protocols.yunji.server import YunjiServer
from polynav.runtime.robot_runtime import RobotRuntime
from tests.helpers.sockets import server_end_nodelay
from tests.protocols.yunji.conftest import Client, Harness, serving

MEGABYTE_PACKET = b"{" + b" " * 1_048_574 + b"\n"


async def _settle(done: Callable[[], bool]) -> bool:
    """Let the loop run until ``done()`` (bounded in loop iterations, not in time)."""
    for _ in range(10_000):
        if done():
            return True
        await asyncio.sleep(0)
    return done()


async def _flood(server: YunjiServer, packets: int) -> None:
    for _ in range(packets):
        server.broadcast(MEGABYTE_PACKET)
        await asyncio.sleep(0)


def test_a_client_that_does_not_read_is_dropped_when_its_queue_overflows(
    harness: Harness,
) -> None:
    small = harness.loop.run(serve(harness.runtime, YunjiConfig(port=0, queue_size=4)))
    try:
        sleeper = Client(small.port)
        harness.clients.append(sleeper)
        assert sleeper.request("/api/robot_info")["status"] == "OK"
        assert small.client_count == 1
        # 20 MB queued to a client that reads nothing: the writer blocks on the first packets,
        # the queue of 4 fills, and the client is disconnected.
        harness.loop.run(_flood(small, 20))
        assert harness.loop.run(_settle(lambda: small.client_count == 0))
        fresh = Client(small.port)
        harness.clients.append(fresh)
        assert fresh.request("/api/robot_info")["status"] == "OK"
    finally:
        harness.loop.run(small.close())


def test_200_clients_connecting_and_dropping_leave_the_server_serving(harness: Harness) -> None:
    for i in range(200):
        c = Client(harness.server.port)
        if i % 2:
            c.send("/api/robot_status")  # some drop with a request in flight
        c.close()
    survivor = harness.client()
    assert survivor.request("/api/robot_info")["status"] == "OK"
    assert harness.loop.run(_settle(lambda: harness.server.client_count == 1))


def test_a_handler_crash_is_unknown_error_and_the_connection_stays(
    harness: Harness, client: Client, monkeypatch: pytest.MonkeyPatch
) -> None:
    def broken(ctx: context.Context, params: context.Params) -> Reply:
        raise RuntimeError("boom")

    monkeypatch.setitem(routes.HANDLERS, "/api/robot_info", broken)
    reply = client.request("/api/robot_info?uuid=x")
    assert (reply["command"], reply["uuid"], reply["status"], reply["error_message"]) == (
        "/api/robot_info", "x", "UNKNOWN_ERROR", "internal error")
    assert client.request("/api/markers/count")["status"] == "OK"


@pytest.mark.parametrize(
    ("exc", "expected"),
    [
        (InvalidRequest("x", "bad"), (Status.INVALID_REQUEST, "x: bad")),
        (NotFound("point", "m1"), (Status.INVALID_REQUEST, "Marker Not Found")),
        (NotFound("map", "m1"), (Status.INVALID_REQUEST, "map 'm1' not found")),
        (Conflict("busy"), (Status.REQUEST_DENIED, "busy")),
        (PolynavError("disk"), (Status.UNKNOWN_ERROR, "disk")),
        (ValueError("no"), (Status.UNKNOWN_ERROR, "internal error")),
    ],
)
def test_status_for_follows_the_mro(exc: BaseException, expected: tuple[Status, str]) -> None:
    assert errors.status_for(exc) == expected


def test_accepted_tcp_and_http_connections_have_nodelay(runtime: RobotRuntime) -> None:
    with serving(runtime, YunjiConfig(port=0, http_port=0)) as h:
        tcp = h.client()
        assert tcp.request("/api/robot_info")["status"] == "OK"
        assert server_end_nodelay(tcp.sock) == 1
        assert h.server.http_port is not None
        with socket.create_connection(("127.0.0.1", h.server.http_port)) as raw:
            raw.sendall(b"GET /api/robot_info HTTP/1.1\r\nHost: x\r\n\r\n")
            assert raw.recv(12).startswith(b"HTTP/1.1")
            assert server_end_nodelay(raw) == 1
