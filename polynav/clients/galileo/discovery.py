"""The robots on the LAN, from their UDP announcements (galileo-wire-protocols §6.2).

A Galileo robot sends ``{"id", "port", "mac", "version"}`` to port 22002 about once a second;
the sender's address is the robot's. A robot not heard for :data:`STALE_AFTER` seconds is no
longer online. polynav sends its announcements to the loopback broadcast address unless told
otherwise; a socket bound to the port on all addresses receives both.
"""

from __future__ import annotations

import contextlib
import json
import logging
import socket
import threading
import time

from polynav.clients.galileo.codes import ServerInfo

log = logging.getLogger(__name__)

DISCOVERY_PORT = 22002
STALE_AFTER = 5.0  # [s] wall


class BroadcastReceiver:
    """Listens for announcements on ``port`` in a daemon thread."""

    def __init__(self, port: int = DISCOVERY_PORT, host: str = "") -> None:
        self._sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self._sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        if hasattr(socket, "SO_REUSEPORT"):
            self._sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEPORT, 1)
        self._sock.bind((host, port))
        self._sock.settimeout(0.2)
        self._servers: dict[str, ServerInfo] = {}
        self._lock = threading.Lock()
        self._heard = threading.Condition(self._lock)
        self._closed = threading.Event()
        self._thread = threading.Thread(target=self._listen, name="galileo-sdk-discovery",
                                        daemon=True)
        self._thread.start()

    @property
    def port(self) -> int:
        """The port listened on (the one chosen when given 0)."""
        return int(self._sock.getsockname()[1])

    def servers(self) -> list[ServerInfo]:
        """The robots heard within :data:`STALE_AFTER` seconds."""
        now = time.monotonic()
        with self._lock:
            return [s for s in self._servers.values() if now - s.timestamp <= STALE_AFTER]

    def wait(self, seconds: float) -> None:
        """Until the next announcement or ``seconds``."""
        with self._heard:
            self._heard.wait(seconds)

    def close(self) -> None:
        self._closed.set()
        self._thread.join(timeout=2.0)
        with contextlib.suppress(OSError):
            self._sock.close()

    def _listen(self) -> None:
        while not self._closed.is_set():
            try:
                data, (address, _) = self._sock.recvfrom(4096)
            except TimeoutError:
                continue
            except OSError:
                return
            try:
                doc = json.loads(data)
                info = ServerInfo(str(doc["id"]), str(doc.get("mac", "")), int(doc["port"]),
                                  address, str(doc.get("version", "")), time.monotonic())
            except (ValueError, KeyError, TypeError):
                log.debug("galileo sdk: not an announcement from %s: %r", address, data[:80])
                continue
            with self._heard:
                self._servers[info.ID] = info
                self._heard.notify_all()
