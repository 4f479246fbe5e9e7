"""UDP discovery (issue item 8; galileo-http-a §1.2): the robot announces itself once a second.

The announcement is one JSON datagram, ``{"id", "port", "mac", "version"}``, sent to port 22002
of the broadcast address: ``127.255.255.255`` (loopback broadcast) unless a LAN broadcast
address is configured, so nothing leaves the machine by default (DESIGN §7). On Linux a datagram
to 127.255.255.255 reaches sockets bound to that address or to 0.0.0.0 on the port (not those
bound to 127.0.0.1). The socket sends from the HTTP server's host address, because real clients
take the robot's address from the sender and ignore ``port`` (issue item 11); ``port`` is the
HTTP port all the same. Sending runs on wall time: it is transport, not robot behaviour.
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import logging
import socket
from collections.abc import Callable

log = logging.getLogger(__name__)


def announcement(*, robot_id: str, port: int, mac: str, version: str) -> bytes:
    """The datagram, keys in the document's order."""
    return json.dumps(
        {"id": robot_id, "port": port, "mac": mac, "version": version}, separators=(", ", ": ")
    ).encode("utf-8")


class Announcer:
    """Sends ``payload()`` to ``(address, port)`` every ``interval`` seconds until closed."""

    def __init__(
        self,
        payload: Callable[[], bytes],
        *,
        address: str,
        port: int,
        interval: float,
        source: str | None,
    ) -> None:
        self._payload = payload
        self._target = (address, port)
        self._interval = interval
        self._source = source
        self._sock: socket.socket | None = None
        self._task: asyncio.Task[None] | None = None
        self.sent = 0

    def start(self) -> None:
        """Open the socket and start sending (the first datagram at once).

        Raises:
            OSError: the socket cannot be opened or bound.
        """
        sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        try:
            sock.setsockopt(socket.SOL_SOCKET, socket.SO_BROADCAST, 1)
            if self._source is not None and self._source not in ("0.0.0.0", ""):
                sock.bind((self._source, 0))
            sock.setblocking(False)
        except BaseException:
            sock.close()
            raise
        self._sock = sock
        self._task = asyncio.ensure_future(self._run())

    async def _run(self) -> None:
        assert self._sock is not None
        while True:
            try:
                self._sock.sendto(self._payload(), self._target)
                self.sent += 1
            except OSError as exc:  # no route for now (interface down): try again later
                log.warning("galileo: discovery announcement to %s:%d failed: %s",
                            *self._target, exc)
            await asyncio.sleep(self._interval)

    async def close(self) -> None:
        if self._task is not None:
            self._task.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await self._task
            self._task = None
        if self._sock is not None:
            self._sock.close()
            self._sock = None
