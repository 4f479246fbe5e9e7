"""The Galileo adapter's servers around one runtime: HTTP (3546), UDP discovery (22002) and the
WebSocket (3547). Transport only (STYLE R4): the handlers live in the route modules.
"""

from __future__ import annotations

import hashlib
import logging

from polynav.protocols.galileo import routes
from polynav.protocols.galileo.auth import TokenBook, load_settings
from polynav.protocols.galileo.config import GalileoConfig
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.discovery import Announcer, announcement
from polynav.protocols.galileo.http import create_app
from polynav.protocols.galileo.modbus import ModbusListener
from polynav.protocols.galileo.native.serial_link import SerialLink
from polynav.protocols.galileo.udp_fast import UdpFastListener
from polynav.protocols.galileo.ws import WsListener
from polynav.protocols.http_listener import HttpListener
from polynav.protocols.server_thread import ServerThread, started
from polynav.protocols.site_store import site_store
from polynav.runtime.robot_runtime import RobotRuntime

log = logging.getLogger(__name__)

#: The Galileo HTTP API version polynav answers to (the spec's examples are 5.0–6.x).
API_VERSION = "6.1.5"


def identity(seed: str) -> tuple[str, str]:
    """A stable robot id (76 upper-case hex digits, like the vendor's) and a locally
    administered MAC address, both derived from ``seed`` (the data directory)."""
    digest = hashlib.sha512(seed.encode("utf-8")).hexdigest().upper()
    robot_id = (digest + hashlib.sha256(seed.encode("utf-8")).hexdigest().upper())[:76]
    octets = [int(digest[i : i + 2], 16) for i in range(0, 12, 2)]
    octets[0] = (octets[0] | 0x02) & 0xFE  # locally administered, unicast
    return robot_id, ":".join(f"{o:02x}" for o in octets)


def make_context(runtime: RobotRuntime, config: GalileoConfig) -> Context:
    data_dir = site_store(runtime).data_dir
    config_file = config.config_file or data_dir / "galileo" / "config.json"
    settings = load_settings(config_file)
    robot_id, mac = identity(str(data_dir.resolve()))
    return Context(
        runtime=runtime,
        config=config,
        tokens=TokenBook(settings, require_token=config.require_token),
        robot_id=config.robot_id or robot_id,
        mac=mac,
        version=API_VERSION,
        data_dir=data_dir,
    )


class GalileoServer:
    """The listening Galileo servers; build with :func:`serve`, end with :meth:`close`."""

    def __init__(self, runtime: RobotRuntime, config: GalileoConfig) -> None:
        self.config = config
        self.ctx = make_context(runtime, config)
        self._http: HttpListener | None = None
        self._announcer: Announcer | None = None
        self._ws: WsListener | None = None
        self._serial: SerialLink | None = None
        self._modbus: ModbusListener | None = None
        self._udp_fast: UdpFastListener | None = None

    @property
    def ws_port(self) -> int | None:
        """The WebSocket port actually bound, if it serves."""
        return None if self._ws is None else self._ws.port

    @property
    def modbus_port(self) -> int | None:
        """The Modbus TCP port actually bound, if it serves."""
        return None if self._modbus is None else self._modbus.port

    @property
    def udp_fast_port(self) -> int | None:
        """The UDP fast protocol's port actually bound, if it serves."""
        return None if self._udp_fast is None else self._udp_fast.port

    @property
    def serial_path(self) -> str | None:
        """The serial line's path (the pty a host opens), if the serial protocol is served."""
        return None if self._serial is None else self._serial.path

    @property
    def port(self) -> int:
        """The HTTP port actually bound."""
        assert self._http is not None
        return self._http.port

    async def start(self) -> None:
        app = create_app(self.ctx, routes.table())
        http = HttpListener(app, self.config.host, self.config.port, name="Galileo HTTP")
        await http.start()
        self._http = http
        log.info("galileo: HTTP on %s:%d (token checking %s)", self.config.host, http.port,
                 "on" if self.ctx.tokens.checking else "off")
        if self.config.ws_port is not None:
            ws = WsListener(self.ctx, self.config.host, self.config.ws_port)
            await ws.start()
            self._ws = ws
            log.info("galileo: WebSocket on %s:%d", self.config.host, ws.port)
        if self.config.modbus_port is not None:
            modbus = ModbusListener(self.ctx, self.config.host, self.config.modbus_port)
            await modbus.start()
            self._modbus = modbus
            log.info("galileo: Modbus TCP on %s:%d", self.config.host, modbus.port)
        if self.config.udp_fast_port is not None:
            udp_fast = UdpFastListener(self.ctx, self.config.host, self.config.udp_fast_port)
            await udp_fast.start()
            self._udp_fast = udp_fast
            log.info("galileo: UDP fast protocol on %s:%d", self.config.host, udp_fast.port)
        if self.config.serial is not None:
            device = None if self.config.serial == "pty" else self.config.serial
            self._serial = SerialLink(self.ctx, device).start()
        if self.config.announce:
            ctx = self.ctx
            payload = announcement(robot_id=ctx.robot_id, port=http.port, mac=ctx.mac,
                                   version=ctx.version)
            announcer = Announcer(
                lambda: payload, address=self.config.broadcast_address,
                port=self.config.udp_port, interval=self.config.announce_interval,
                source=self.config.host,
            )
            announcer.start()
            self._announcer = announcer
            log.info("galileo: announcing on udp %s:%d", self.config.broadcast_address,
                     self.config.udp_port)

    async def close(self) -> None:
        if self._serial is not None:
            self._serial.stop()
            self._serial = None
        if self._modbus is not None:
            await self._modbus.close()
            self._modbus = None
        if self._udp_fast is not None:
            await self._udp_fast.close()
            self._udp_fast = None
        if self._announcer is not None:
            await self._announcer.close()
            self._announcer = None
        if self._ws is not None:
            await self._ws.close()
            self._ws = None
        if self._http is not None:
            await self._http.close()
            self._http = None
        self.ctx.close()


async def serve(runtime: RobotRuntime, config: GalileoConfig | None = None) -> GalileoServer:
    """Start the Galileo servers for ``runtime`` on the running event loop."""
    return await started(GalileoServer(runtime, config or GalileoConfig()))


class GalileoThread(ServerThread[GalileoServer]):
    """The Galileo servers on their own event loop in a daemon thread (``polynav run``)."""

    def __init__(self, runtime: RobotRuntime, config: GalileoConfig) -> None:
        super().__init__("polynav-galileo", lambda: serve(runtime, config))

    @property
    def port(self) -> int:
        return self.server.port

    @property
    def ws_port(self) -> int | None:
        return self.server.ws_port

    @property
    def serial_path(self) -> str | None:
        return self.server.serial_path

    @property
    def modbus_port(self) -> int | None:
        return self.server.modbus_port

    @property
    def udp_fast_port(self) -> int | None:
        return self.server.udp_fast_port
