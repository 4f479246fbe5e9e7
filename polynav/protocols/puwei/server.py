"""The Puwei adapter's servers around one runtime: HTTP + WebSocket on one port (8080) and UDP
discovery (9999). Transport only (STYLE R4): the handlers live in the route modules, the
WebSocket session in ``ws.py``.
"""

from __future__ import annotations

import logging
import socket

from polynav.protocols.http_listener import HttpListener
from polynav.protocols.puwei import routes
from polynav.protocols.puwei.auth import TokenBook
from polynav.protocols.puwei.config import PuweiConfig
from polynav.protocols.puwei.context import Context
from polynav.protocols.puwei.discovery import DiscoveryResponder
from polynav.protocols.puwei.http import create_app
from polynav.protocols.server_thread import ServerThread, started
from polynav.runtime.robot_runtime import RobotRuntime

log = logging.getLogger(__name__)


def own_address(host: str) -> str:
    """The address ``/api/devices`` gives: the bound one, or for all interfaces the host
    name's (loopback when it has none)."""
    if host not in ("0.0.0.0", ""):
        return host
    try:
        return socket.gethostbyname(socket.gethostname())
    except OSError:
        return "127.0.0.1"


class PuweiServer:
    """The listening Puwei servers; build with :func:`serve`, end with :meth:`close`."""

    def __init__(self, runtime: RobotRuntime, config: PuweiConfig) -> None:
        self.config = config
        self.ctx = Context(runtime=runtime, tokens=TokenBook(
            username=config.username, password=config.password, ttl=config.token_ttl))
        address = own_address(config.host)
        self.ctx.state("puwei.address", lambda: address)
        self._http: HttpListener | None = None
        self._discovery: DiscoveryResponder | None = None

    @property
    def port(self) -> int:
        """The HTTP (and WebSocket) port actually bound."""
        assert self._http is not None
        return self._http.port

    @property
    def discovery_port(self) -> int | None:
        """The UDP discovery port actually bound, if it answers."""
        return None if self._discovery is None else self._discovery.port

    async def start(self) -> None:
        http = HttpListener(create_app(self.ctx, routes.table()), self.config.host,
                            self.config.port, name="Puwei HTTP", ws="websockets-sansio")
        await http.start()
        self._http = http
        log.info("puwei: HTTP and WebSocket on %s:%d", self.config.host, http.port)
        if self.config.discovery_port is not None:
            discovery = DiscoveryResponder(
                host=self.config.discovery_host, port=self.config.discovery_port,
                group=self.config.multicast_group, http_port=http.port)
            await discovery.start()
            self._discovery = discovery
            log.info("puwei: discovery on udp %s:%d and group %s", self.config.discovery_host,
                     discovery.port, self.config.multicast_group)

    async def close(self) -> None:
        if self._discovery is not None:
            await self._discovery.close()
            self._discovery = None
        if self._http is not None:
            await self._http.close()
            self._http = None


async def serve(runtime: RobotRuntime, config: PuweiConfig | None = None) -> PuweiServer:
    """Start the Puwei servers for ``runtime`` on the running event loop.

    Raises:
        OSError: a port cannot be bound (nothing is left listening).
    """
    return await started(PuweiServer(runtime, config or PuweiConfig()))


class PuweiThread(ServerThread[PuweiServer]):
    """The Puwei servers on their own event loop in a daemon thread (``polynav run``)."""

    def __init__(self, runtime: RobotRuntime, config: PuweiConfig) -> None:
        super().__init__("polynav-puwei", lambda: serve(runtime, config))

    @property
    def port(self) -> int:
        return self.server.port

    @property
    def discovery_port(self) -> int | None:
        return self.server.discovery_port
