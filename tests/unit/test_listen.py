"""Every listener polynav makes hands out connections with Nagle off (TCP_NODELAY)."""

from __future__ import annotations

import asyncio
import socket

import pytest

from polynav.listen import tcp_listener
from tests.helpers.sockets import server_end_nodelay


def test_a_connection_accepted_from_the_listener_has_nodelay() -> None:
    with tcp_listener("127.0.0.1", 0) as listener:
        listener.setblocking(True)
        with socket.create_connection(listener.getsockname()[:2]) as client:
            accepted, _ = listener.accept()
            with accepted:
                assert accepted.getsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY) == 1
                assert server_end_nodelay(client) == 1


def test_the_listener_is_tcp_by_protocol_number_so_asyncio_sets_nodelay_too() -> None:
    async def run() -> int:
        seen: asyncio.Future[int] = asyncio.get_running_loop().create_future()

        async def handle(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
            sock = writer.get_extra_info("socket")
            seen.set_result(sock.getsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY))
            writer.close()

        server = await asyncio.start_server(handle, sock=tcp_listener("127.0.0.1", 0))
        port = server.sockets[0].getsockname()[1]
        _, writer = await asyncio.open_connection("127.0.0.1", port)
        result = await seen
        writer.close()
        server.close()
        await server.wait_closed()
        return result

    with tcp_listener("127.0.0.1", 0) as listener:
        assert listener.proto == socket.IPPROTO_TCP
    assert asyncio.run(run()) == 1


def test_a_port_in_use_is_an_os_error() -> None:
    with tcp_listener("127.0.0.1", 0) as first:
        with pytest.raises(OSError):
            tcp_listener("127.0.0.1", first.getsockname()[1])
