"""Configuration of the native API server."""

from __future__ import annotations

import ipaddress
import logging
from dataclasses import dataclass

from polynav.errors import ConfigError

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True)
class ApiConfig:
    """Where the native API listens and how its WebSocket streams behave.

    Attributes:
        host: interface to bind; loopback by default so a demo is never exposed by accident.
        port: TCP port [1, 65535], or 0 to let the OS choose (tests).
        ws_default_rate: status messages per SIMULATED second when ``?rate=`` is absent [Hz].
        ws_max_rate: the highest rate a client may ask for [Hz], so a client cannot flood itself.
        ws_poll_interval: how often a WebSocket task looks at the snapshot and the event queue
            [s wall]; small enough to follow the fastest simulated rate, large enough to stay idle.
        ws_map_rate: while mapping, live map messages per SIMULATED second [Hz].
        ws_queue_size: events a WebSocket client may fall behind before it is closed as too slow
            (status messages are coalesced and do not count).
        auth: whether every route but ``POST /api/login`` needs a login (docs/auth.md);
            ``None``: exactly when ``host`` is not a loopback address. Tests force it on.
        session_ttl: how long a login's token (and session cookie) is valid [s wall].
    """

    host: str = "127.0.0.1"
    port: int = 8000
    ws_default_rate: float = 5.0
    ws_max_rate: float = 50.0
    ws_poll_interval: float = 0.005
    ws_queue_size: int = 1000
    ws_map_rate: float = 0.5
    auth: bool | None = None
    session_ttl: float = 12 * 3600.0

    @property
    def login_required(self) -> bool:
        """Whether the API asks for a login: ``auth`` if given, else off loopback only."""
        return not is_loopback(self.host) if self.auth is None else self.auth

    def __post_init__(self) -> None:
        if not self.host:
            raise ConfigError("api.host", "must not be empty")
        if not 60.0 <= self.session_ttl <= 366 * 86400.0:
            raise ConfigError(
                "api.session_ttl", f"must be in [60, {366 * 86400}] s, got {self.session_ttl}"
            )
        if not 0 <= self.port <= 65535:
            raise ConfigError("api.port", f"must be in [0, 65535], got {self.port}")
        if not 0.0 < self.ws_max_rate <= 1000.0:
            raise ConfigError("api.ws_max_rate", f"must be in (0, 1000], got {self.ws_max_rate}")
        if not 0.0 < self.ws_default_rate <= self.ws_max_rate:
            raise ConfigError(
                "api.ws_default_rate",
                f"must be in (0, ws_max_rate={self.ws_max_rate}], got {self.ws_default_rate}",
            )
        if not 0.0 < self.ws_map_rate <= 10.0:
            raise ConfigError("api.ws_map_rate", f"must be in (0, 10], got {self.ws_map_rate}")
        if not 1 <= self.ws_queue_size <= 1_000_000:
            raise ConfigError(
                "api.ws_queue_size", f"must be in [1, 1000000], got {self.ws_queue_size}"
            )
        if not 0.0 < self.ws_poll_interval <= 1.0:
            raise ConfigError(
                "api.ws_poll_interval", f"must be in (0, 1], got {self.ws_poll_interval}"
            )


def is_loopback(host: str) -> bool:
    """Whether binding ``host`` keeps the API on this machine: a loopback address or
    ``localhost``. Any other name or address (``0.0.0.0``, a LAN name) counts as exposed."""
    if host.lower() == "localhost":
        return True
    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        return False
