"""The rosbridge v2 server: a ROS graph on a WebSocket, as rosbridge_server serves ROS.

The server knows nothing of the runtime: it serves a :class:`~polynav.protocols.ros_graph.Graph`
(the dialect mappings fill it) and the rosapi services over it, on the clock it is given.
Messages the graph publishes (from the runtime's loop thread) are written to JSON once per
message, on the server's loop, and only when a client subscribes to their topic.
"""

from __future__ import annotations

import asyncio
import logging
import socket
from collections import defaultdict
from collections.abc import Callable

from websockets.asyncio.server import Server, ServerConnection, serve

from polynav.clock import Clock
from polynav.listen import tcp_listener
from polynav.protocols.ros_graph import Graph, Message, Service
from polynav.protocols.rosbridge.config import RosbridgeConfig
from polynav.protocols.rosbridge.connection import Connection
from polynav.protocols.rosbridge.rosapi import rosapi_services
from polynav.protocols.rosbridge.wire import dumps
from polynav.protocols.server_thread import ServerThread, started

log = logging.getLogger(__name__)


class RosbridgeServer:
    """The listening server; build with :func:`serve_rosbridge`, end with :meth:`close`."""

    def __init__(self, graph: Graph, clock: Clock, config: RosbridgeConfig) -> None:
        self.graph = graph
        self.clock = clock
        self.config = config
        self._rosapi = rosapi_services(graph, clock)
        self._connections: set[Connection] = set()
        self._subscribers: dict[str, set[Connection]] = defaultdict(set)
        # Topics someone subscribes to: read by the graph's publishing threads (a set lookup),
        # replaced whole on the loop.
        self._wanted: frozenset[str] = frozenset()
        self._server: Server | None = None
        self._sock: socket.socket | None = None
        self._loop: asyncio.AbstractEventLoop | None = None
        self._remove_sink: Callable[[], None] = _nothing

    @property
    def port(self) -> int:
        """The port actually bound."""
        assert self._sock is not None
        return int(self._sock.getsockname()[1])

    async def start(self) -> None:
        """Bind and serve. Raises ``OSError`` when the port cannot be bound."""
        self._loop = asyncio.get_running_loop()
        self._sock = tcp_listener(self.config.host, self.config.port)
        self._server = await serve(self._serve, sock=self._sock,
                                   max_size=self.config.max_message_size, compression=None)
        self._remove_sink = self.graph.add_sink(self._on_message)
        log.info("rosbridge: on %s:%d", self.config.host, self.port)

    async def close(self) -> None:
        self._remove_sink()
        if self._server is not None:
            self._server.close()
            await self._server.wait_closed()
            self._server = None
        if self._sock is not None:
            self._sock.close()
            self._sock = None

    @property
    def clients(self) -> int:
        """Clients connected now."""
        return len(self._connections)

    # -- what connections ask of the server ------------------------------------------------------

    def service(self, name: str) -> Service | None:
        """A rosapi service or one of the graph's."""
        return self._rosapi.get(name) or self.graph.service(name)

    def service_names(self) -> list[str]:
        return sorted({*self._rosapi, *(s.name for s in self.graph.services())})

    def subscribed(self, connection: Connection, topic: str) -> None:
        """``connection`` subscribes to ``topic``: it gets a latched topic's last message."""
        first = connection not in self._subscribers[topic]
        self._subscribers[topic].add(connection)
        if first:
            self.graph.retain(topic)
        self._wanted = frozenset(t for t, c in self._subscribers.items() if c)
        last = self.graph.latched(topic)
        if first and last is not None:
            connection.deliver(topic, _publish_frame(topic, last))

    def unsubscribed(self, connection: Connection, topic: str) -> None:
        if connection in self._subscribers[topic]:
            self._subscribers[topic].discard(connection)
            self.graph.release(topic)
        self._wanted = frozenset(t for t, c in self._subscribers.items() if c)

    def forget(self, connection: Connection) -> None:
        """``connection`` has gone."""
        self._connections.discard(connection)
        for topic in connection.topics:
            if connection in self._subscribers[topic]:
                self._subscribers[topic].discard(connection)
                self.graph.release(topic)
        self._wanted = frozenset(t for t, c in self._subscribers.items() if c)

    # -- the loop ----------------------------------------------------------------------------------

    async def _serve(self, ws: ServerConnection) -> None:
        connection = Connection(self, ws)
        self._connections.add(connection)
        await connection.run()

    def _on_message(self, topic: str, message: Message) -> None:
        """The graph's sink (any thread): hand a wanted message to the loop."""
        if topic not in self._wanted or self._loop is None:
            return
        try:
            self._loop.call_soon_threadsafe(self._fan_out, topic, message)
        except RuntimeError:  # the loop has closed: the server is going
            pass

    def _fan_out(self, topic: str, message: Message) -> None:
        subscribers = self._subscribers.get(topic)
        if not subscribers:
            return
        text = _publish_frame(topic, message)
        for connection in tuple(subscribers):
            connection.deliver(topic, text)


def _nothing() -> None:
    pass


def _publish_frame(topic: str, message: Message) -> str:
    return dumps({"op": "publish", "topic": topic, "msg": message})


async def serve_rosbridge(graph: Graph, clock: Clock,
                          config: RosbridgeConfig | None = None) -> RosbridgeServer:
    """Start a rosbridge server for ``graph`` on the running loop.

    Raises:
        OSError: the port cannot be bound.
    """
    return await started(RosbridgeServer(graph, clock, config or RosbridgeConfig()))


class RosbridgeThread(ServerThread[RosbridgeServer]):
    """The rosbridge server on its own event loop in a daemon thread (``polynav run``)."""

    def __init__(self, graph: Graph, clock: Clock, config: RosbridgeConfig) -> None:
        super().__init__("polynav-rosbridge", lambda: serve_rosbridge(graph, clock, config))

    @property
    def port(self) -> int:
        return self.server.port
