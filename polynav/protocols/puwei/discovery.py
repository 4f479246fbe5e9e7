"""UDP discovery (puwei-api §3.1): answer ``discovery`` with a string starting ``puwei``.

Two sockets listen on the discovery port (9999): one on the configured interface's address
(unicast), one on the multicast group (224.0.0.1) joined on that interface only: loopback
unless a LAN interface is configured (DESIGN §7), so a datagram from the LAN is never answered
by default. Unicast to the
port is answered too. The reply goes to the sender alone (never to the group), as
``puwei <http port>``: the client takes the robot's address from the reply's source (A5) and
learns the port it serves on. Anything else than ``discovery`` gets no answer. Transport only,
on the adapter's event loop.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import socket
import struct
from typing import cast

log = logging.getLogger(__name__)

REQUEST = b"discovery"
PREFIX = "puwei"


def reply(http_port: int) -> bytes:
    """The answer: ``puwei <http port>``."""
    return f"{PREFIX} {http_port}".encode("ascii")


#: Linux: deliver a group's datagrams only to sockets that joined it themselves (by default
#: a socket gets every group any socket of the machine joined, on any interface).
IP_MULTICAST_ALL = getattr(socket, "IP_MULTICAST_ALL", 49)


class _Responder(asyncio.DatagramProtocol):
    """Receives on one socket; replies go out through ``send`` (the unicast socket: a socket
    bound to a group address cannot be a datagram's source)."""

    def __init__(self, payload: bytes, send: _Responder | None = None) -> None:
        self._payload = payload
        self._send = send
        self.transport: asyncio.DatagramTransport | None = None

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        # The loop's datagram transport (not a subclass of DatagramTransport everywhere).
        self.transport = cast(asyncio.DatagramTransport, transport)

    def datagram_received(self, data: bytes, addr: tuple[str | int, ...]) -> None:
        if data.strip() != REQUEST:
            return
        sender = self._send if self._send is not None else self
        if sender.transport is None or sender.transport.is_closing():
            return
        sender.transport.sendto(self._payload, addr)
        log.debug("puwei: discovery answered to %s:%s", addr[0], addr[1])

    def error_received(self, exc: Exception) -> None:
        log.debug("puwei: discovery socket error: %s", exc)


def _udp(address: tuple[str, int]) -> socket.socket:
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM, socket.IPPROTO_UDP)
    try:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        sock.bind(address)
        sock.setblocking(False)
    except BaseException:
        sock.close()
        raise
    return sock


def sockets(host: str, port: int, group: str) -> tuple[socket.socket, socket.socket]:
    """(unicast, group) sockets on one port: the first bound to ``host``, the second to the
    group address and joined to it on interface ``host`` only.

    A socket bound to a unicast address gets no multicast, and one bound to the wildcard
    would listen on every interface, hence two. With ``IP_MULTICAST_ALL`` off and the
    membership naming the interface, the group socket receives only what reaches ``host``'s
    interface (loopback by default: nothing from the LAN).

    Raises:
        OSError: the port cannot be bound or the group joined.
    """
    unicast = _udp((host, port))
    try:
        bound = unicast.getsockname()[1]
        multicast = _udp((group, bound))
        try:
            with contextlib.suppress(OSError):  # not Linux: the option does not exist
                multicast.setsockopt(socket.IPPROTO_IP, IP_MULTICAST_ALL, 0)
            interface = "0.0.0.0" if host in ("", "0.0.0.0") else host
            membership = struct.pack("=4s4s", socket.inet_aton(group),
                                     socket.inet_aton(interface))
            multicast.setsockopt(socket.IPPROTO_IP, socket.IP_ADD_MEMBERSHIP, membership)
        except BaseException:
            multicast.close()
            raise
    except BaseException:
        unicast.close()
        raise
    return unicast, multicast


class DiscoveryResponder:
    """Answers discovery requests until closed."""

    def __init__(self, *, host: str, port: int, group: str, http_port: int) -> None:
        self._host = host
        self._port = port
        self._group = group
        self._payload = reply(http_port)
        self._unicast: _Responder | None = None
        self._multicast: _Responder | None = None

    @property
    def port(self) -> int:
        """The UDP port actually bound."""
        assert self._unicast is not None and self._unicast.transport is not None
        return int(self._unicast.transport.get_extra_info("sockname")[1])

    async def start(self) -> None:
        """Bind and join.

        Raises:
            OSError: the port cannot be bound or the group joined.
        """
        unicast_sock, multicast_sock = sockets(self._host, self._port, self._group)
        loop = asyncio.get_running_loop()
        try:
            _, unicast = await loop.create_datagram_endpoint(
                lambda: _Responder(self._payload), sock=unicast_sock)
        except BaseException:
            unicast_sock.close()
            multicast_sock.close()
            raise
        self._unicast = unicast
        try:
            _, multicast = await loop.create_datagram_endpoint(
                lambda: _Responder(self._payload, unicast), sock=multicast_sock)
        except BaseException:
            multicast_sock.close()
            await self.close()
            raise
        self._multicast = multicast

    async def close(self) -> None:
        for protocol in (self._multicast, self._unicast):
            if protocol is not None and protocol.transport is not None:
                protocol.transport.close()
        self._unicast = self._multicast = None
