"""The Galileo adapter's configuration: where it listens and how it checks tokens.

The vendor keeps its HTTP service settings in a ``config.json`` (spec galileo-http-a §1.3):
``username``, ``password``, ``allow_update``, ``no_token_check``, ``auto_charge``. polynav reads the
same file from ``<data>/galileo/config.json`` (:mod:`polynav.protocols.galileo.auth`); this class
holds what polynav adds around it (ports, the bind address, and ``require_token``, which forces
token checking on whatever the file says).
"""

from __future__ import annotations

import ipaddress
from dataclasses import dataclass
from pathlib import Path

from polynav.errors import ConfigError

DEFAULT_HTTP_PORT = 3546
DEFAULT_WS_PORT = 3547
DEFAULT_UDP_PORT = 22002
DEFAULT_MODBUS_PORT = 3551


@dataclass(frozen=True, slots=True)
class GalileoConfig:
    """How the Galileo adapter serves.

    Attributes:
        host: interface to bind; loopback unless configured.
        port: HTTP port (3546 on the robot); 0 lets the OS choose (tests).
        ws_port: WebSocket port (3547); 0: any; ``None``: no WebSocket server.
        config_file: the vendor-format ``config.json``; ``None``: ``<data>/galileo/config.json``.
        require_token: check tokens even when ``config.json`` says ``no_token_check: true``.
        announce: send the UDP discovery announcement.
        udp_port: the announcement's destination port (22002).
        broadcast_address: where announcements go; loopback broadcast unless a LAN broadcast
            address is configured (DESIGN §7).
        announce_interval: seconds [wall] between announcements (the spec: about once a second).
        robot_id: the ``id`` of the announcement and ``/system/info``; ``None``: derived from
            the data directory, stable across restarts.
        serial: the navigation serial port: a device path (``/dev/ttyUSB0``), ``"pty"`` for a
            new pseudo-terminal, ``None``: none (galileo-wire-protocols §1).
        modbus_port: the Modbus TCP port (3551 on the robot, §3); 0: any; ``None``: none.
        udp_fast_port: the UDP fast protocol's port (3547/udp, §4); 0: any; ``None``: none.
    """

    host: str = "127.0.0.1"
    port: int = DEFAULT_HTTP_PORT
    ws_port: int | None = DEFAULT_WS_PORT
    config_file: Path | None = None
    require_token: bool = False
    announce: bool = True
    udp_port: int = DEFAULT_UDP_PORT
    broadcast_address: str = "127.255.255.255"
    announce_interval: float = 1.0
    robot_id: str | None = None
    serial: str | None = None
    modbus_port: int | None = None
    udp_fast_port: int | None = None

    def __post_init__(self) -> None:
        if not self.host:
            raise ConfigError("galileo.host", "must not be empty")
        for key in ("port", "udp_port"):
            value = getattr(self, key)
            if not 0 <= value <= 65535:
                raise ConfigError(f"galileo.{key}", f"must be in [0, 65535], got {value}")
        for key in ("ws_port", "modbus_port", "udp_fast_port"):
            value = getattr(self, key)
            if value is not None and not 0 <= value <= 65535:
                raise ConfigError(f"galileo.{key}", f"must be in [0, 65535], got {value}")
        if self.serial is not None and not self.serial:
            raise ConfigError("galileo.serial", "a device path, or 'pty'")
        if not 0.05 <= self.announce_interval <= 60.0:
            raise ConfigError(
                "galileo.announce_interval",
                f"must be in [0.05, 60] s, got {self.announce_interval}",
            )
        if self.announce and self.udp_port == 0:
            raise ConfigError("galileo.udp_port",
                              "announcements need a destination port in [1, 65535]")
        try:
            ipaddress.IPv4Address(self.broadcast_address)
        except ValueError:
            raise ConfigError("galileo.broadcast_address",
                              f"must be an IPv4 address, got {self.broadcast_address!r}"
                              ) from None
