"""The rosbridge server's settings."""

from __future__ import annotations

from dataclasses import dataclass

from polynav.errors import ConfigError

#: rosbridge_server's port.
DEFAULT_PORT = 9090


@dataclass(frozen=True, slots=True)
class RosbridgeConfig:
    """Where the server listens and what one client may cost.

    Attributes:
        host: interface to bind (loopback unless the user says otherwise).
        port: TCP port; 0 picks a free one.
        max_message_size: the largest frame a client may send [bytes]; a larger one closes the
            connection with 1009 (message too big), as rosbridge's WebSocket server does with
            its 10 MiB default.
        max_queue_length: a subscription's ``queue_length`` is capped at this (messages kept
            for a slow or throttled subscriber, the oldest dropped first).
        max_replies: service responses and status messages that may wait unsent; beyond
            them the client is closed as not reading (1008), never grown without bound.
        send_timeout: a frame the client has not taken within this many wall seconds closes
            the connection as not reading.
        max_fragments: fragmented messages a client may have half-sent at once.
    """

    host: str = "127.0.0.1"
    port: int = DEFAULT_PORT
    max_message_size: int = 10 * 1024 * 1024
    max_queue_length: int = 100
    max_replies: int = 1000
    send_timeout: float = 10.0
    max_fragments: int = 16

    def __post_init__(self) -> None:
        if not 0 <= self.port <= 65535:
            raise ConfigError("rosbridge.port", f"must be 0-65535, got {self.port}")
        for name in ("max_message_size", "max_queue_length", "max_replies", "max_fragments"):
            if getattr(self, name) < 1:
                raise ConfigError(f"rosbridge.{name}", f"must be >= 1, got {getattr(self, name)}")
        if not self.send_timeout > 0:
            raise ConfigError("rosbridge.send_timeout", f"must be > 0, got {self.send_timeout}")
