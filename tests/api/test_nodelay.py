"""The native API's connections have Nagle off: kept-alive requests answer at wire speed."""

from __future__ import annotations

import socket

import httpx

from tests.helpers.sockets import server_end_nodelay


def test_an_accepted_native_api_connection_has_nodelay(client: httpx.Client) -> None:
    port = int(str(client.base_url).rsplit(":", 1)[1].rstrip("/"))
    with socket.create_connection(("127.0.0.1", port)) as raw:
        raw.sendall(b"GET /api/status HTTP/1.1\r\nHost: x\r\n\r\n")
        assert raw.recv(12).startswith(b"HTTP/1.1")
        assert server_end_nodelay(raw) == 1
