"""The Puwei adapter's configuration: where it listens, its login and its UDP discovery.

The vendor serves HTTP and the WebSocket on one port, 8080 (puwei-api §1), and answers the
string ``discovery`` sent to UDP 224.0.0.1:9999 (§3.1). polynav binds loopback and joins the
multicast group on the loopback interface unless told otherwise (DESIGN §7), so nothing
leaves the machine by default.
"""

from __future__ import annotations

import ipaddress
from dataclasses import dataclass

from polynav.errors import ConfigError

DEFAULT_PORT = 8080
DEFAULT_DISCOVERY_PORT = 9999
MULTICAST_GROUP = "224.0.0.1"


@dataclass(frozen=True, slots=True)
class PuweiConfig:
    """How the Puwei adapter serves.

    Attributes:
        host: interface to bind HTTP and the WebSocket; loopback unless configured.
        port: the HTTP + WebSocket port (8080 on the robot); 0 lets the OS choose.
        discovery_port: the UDP discovery port (9999); 0: any free port (tests); ``None``: no
            discovery.
        discovery_host: the interface the discovery socket binds and joins the multicast group
            on; loopback unless a LAN interface is configured.
        multicast_group: the group joined (the vendor's 224.0.0.1).
        username: the login's user name (the spec's example and presumed default, A3).
        password: the login's password.
        token_ttl: how long a token stays valid [s, wall clock]; 0: until the server stops.
    """

    host: str = "127.0.0.1"
    port: int = DEFAULT_PORT
    discovery_port: int | None = DEFAULT_DISCOVERY_PORT
    discovery_host: str = "127.0.0.1"
    multicast_group: str = MULTICAST_GROUP
    username: str = "admin"
    password: str = "admin"
    token_ttl: float = 0.0

    def __post_init__(self) -> None:
        if not self.host:
            raise ConfigError("puwei.host", "must not be empty")
        if not 0 <= self.port <= 65535:
            raise ConfigError("puwei.port", f"must be in [0, 65535], got {self.port}")
        if self.discovery_port is not None and not 0 <= self.discovery_port <= 65535:
            raise ConfigError("puwei.discovery_port",
                              f"must be in [0, 65535], got {self.discovery_port}")
        try:
            group = ipaddress.IPv4Address(self.multicast_group)
        except ValueError:
            raise ConfigError("puwei.multicast_group",
                              f"not an IPv4 address: {self.multicast_group!r}") from None
        if not group.is_multicast:
            raise ConfigError("puwei.multicast_group", f"{group} is not a multicast address")
        if self.token_ttl < 0:
            raise ConfigError("puwei.token_ttl", f"must be >= 0, got {self.token_ttl}")
        if not self.username:
            raise ConfigError("puwei.username", "must not be empty")
