"""The Galileo WebSocket transport (port 3547): ``ws://host:3547/<topic>?token=``.

One connection serves one topic (galileo-tasks-bt-ws §8). The handshake is refused with HTTP
401 when token checking is on and the token is missing or wrong, and with 404 for a topic polynav
does not serve, so a client learns at once. A subscribed topic is sent at its rate on the
runtime's clock (polled every ``poll_interval`` wall seconds; after a jump of the clock at most one
message catches up); ``/map`` is sent on subscribing and whenever the map changes. Text the
client sends is a message to publish on that topic (``/cmd_vel``); ``"ping"`` and anything sent
to a topic that takes no messages is ignored; a message that does not parse is answered with an
error object and the connection stays. WebSocket pings are answered by the library.
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import socket
from http import HTTPStatus
from typing import Any
from urllib.parse import parse_qs, urlsplit

from websockets.asyncio.server import Server, ServerConnection, serve
from websockets.datastructures import Headers
from websockets.exceptions import ConnectionClosed
from websockets.http11 import Request, Response

from polynav.errors import PolynavError
from polynav.listen import tcp_listener
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.topic_feed import TopicFeed
from polynav.protocols.galileo.topics import TOPICS, Topic


def _refuse(status: HTTPStatus, description: str) -> Response:
    body = json.dumps({"status": "error", "description": description}).encode()
    headers = Headers([("Content-Type", "application/json"),
                       ("Content-Length", str(len(body)))])
    return Response(status.value, status.phrase, headers, body)


class WsListener:
    """The WebSocket server on the running event loop."""

    def __init__(self, ctx: Context, host: str, port: int, *, poll_interval: float = 0.01
                 ) -> None:
        self._ctx = ctx
        self._host = host
        self._port = port
        self._poll = poll_interval
        self._server: Server | None = None
        self._sock: socket.socket | None = None

    @property
    def port(self) -> int:
        assert self._sock is not None
        return int(self._sock.getsockname()[1])

    async def start(self) -> None:
        """Bind and serve. Raises ``OSError`` when the port cannot be bound."""
        self._sock = tcp_listener(self._host, self._port)
        self._server = await serve(
            self._serve, sock=self._sock, process_request=self._check, max_size=1_048_576,
        )

    async def close(self) -> None:
        if self._server is not None:
            self._server.close()
            await self._server.wait_closed()
            self._server = None
        if self._sock is not None:
            self._sock.close()
            self._sock = None

    def _check(self, connection: ServerConnection, request: Request) -> Response | None:
        path, query = _split(request.path)
        if path not in TOPICS:
            return _refuse(HTTPStatus.NOT_FOUND, f"unknown topic {path}")
        token = query.get("token", [None])[0]
        if not self._ctx.tokens.accepts(token):
            return _refuse(HTTPStatus.UNAUTHORIZED, "invalid token")
        return None

    async def _serve(self, connection: ServerConnection) -> None:
        path, _ = _split(connection.request.path if connection.request else "/")
        topic = TOPICS[path]
        sender = asyncio.ensure_future(self._send_loop(connection, topic))
        try:
            async for message in connection:
                await self._receive(connection, topic, message)
        except ConnectionClosed:
            pass
        finally:
            sender.cancel()
            with contextlib.suppress(asyncio.CancelledError, ConnectionClosed):
                await sender

    async def _receive(self, connection: ServerConnection, topic: Topic,
                       message: str | bytes) -> None:
        text = message.decode("utf-8", "replace") if isinstance(message, bytes) else message
        if text.strip().lower() == "ping" or topic.publish is None:
            return
        try:
            data: Any = json.loads(text)
            await asyncio.to_thread(topic.publish, self._ctx, data)
        except (ValueError, PolynavError) as exc:
            await connection.send(json.dumps({"status": "error", "description": str(exc)}))

    async def _send_loop(self, connection: ServerConnection, topic: Topic) -> None:
        feed = TopicFeed(self._ctx, topic)
        if not feed.sends:
            return
        while True:
            if feed.take_due():
                text = await asyncio.to_thread(feed.render)
                if text is not None:
                    await connection.send(text)
            await asyncio.sleep(self._poll)


def _split(target: str) -> tuple[str, dict[str, list[str]]]:
    parts = urlsplit(target)
    return parts.path, parse_qs(parts.query)
