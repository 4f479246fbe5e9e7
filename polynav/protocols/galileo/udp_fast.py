"""Galileo's UDP fast protocol (galileo-wire-protocols §4): a WebSocket emulated over UDP, on
3547/udp beside the WebSocket's 3547/tcp.

A client registers with a connection frame naming one topic and the token; the server checks
both as the WebSocket handshake does (the same topic table and :class:`TokenBook`) and answers
with a 4-byte client id, or ``status: false`` and the reason. From then on, as on the WebSocket,
the topic's messages go to the client at the topic's rate on the runtime's clock
(:class:`~polynav.protocols.galileo.topic_feed.TopicFeed`), and the JSON the client sends is
published on the topic (``/cmd_vel`` drives, ``/galileo/cmds`` runs a native command).

Keep-alive is the network's matter, so it runs on the wall clock: the server pings each client
every ``ping_interval``, answers a ping with a pong, and drops a client it has heard nothing
from for ``client_timeout`` (the example clients give up on a silent server after 10 s, the
default here too), telling it with a CLOSE frame. A client's CLOSE drops it without a reply.

Bounded per client: outgoing frames go through an :class:`~polynav.protocols.outbox.Outbox`
(topic messages, pings and pongs coalesce to the newest; error replies count, and a client that
lets more pile up is dropped), messages waiting to be published are at most
:data:`INBOX_LIMIT`, and long messages are sent in bursts so a burst of ``/map`` chunks does not
overrun a receiver's socket buffer. Datagrams that are not this protocol, truncated, oversized,
or carry an id the server did not give to that sender are dropped; a data frame with an id the
server does not know (a client of a previous run) is answered with CLOSE.
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import logging
import secrets
import socket
import time
from dataclasses import dataclass, field
from typing import Any

from polynav.errors import PolynavError
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.diagnostics import diagnostics
from polynav.protocols.galileo.topic_feed import TopicFeed
from polynav.protocols.galileo.topics import TOPICS, Topic
from polynav.protocols.galileo.udp_fast_frames import (
    CONNECT,
    DATA,
    BadConnectFrame,
    MessageTooLong,
    Opcode,
    PackageCounter,
    Reassembler,
    connect_reply,
    header,
    message_frames,
    parse_connect,
    parse_data,
)
from polynav.protocols.outbox import Outbox, OutboxClosed

log = logging.getLogger(__name__)

#: The robot's port: the WebSocket's number, over UDP (§4.2).
DEFAULT_UDP_FAST_PORT = 3547
#: Error replies that may wait unsent before a client is dropped as not reading.
OUTBOX_LIMIT = 64
#: Messages from one client that may wait to be published; past it they are refused.
INBOX_LIMIT = 64
#: Clients registered at once; past it a registration is refused.
MAX_CLIENTS = 64
#: The longest message sent (a larger one is logged and skipped): 32768 BINARY chunks.
MAX_OUTBOUND_MESSAGE = 16 * 1024 * 1024
#: [bytes] the socket's receive buffer asked for.
RECEIVE_BUFFER = 1024 * 1024
#: Datagrams sent back to back before the writer yields for BURST_PAUSE [s wall].
BURST = 64
BURST_PAUSE = 0.002

Address = tuple[str, int]
#: A frame in a client's outbox: a datagram ready to send, or a message's JSON text (split into
#: datagrams when it is sent, so package indices follow the order of sending).
Outgoing = bytes | str


@dataclass(eq=False)
class _Client:
    """One registered client: where it is, its topic and what is queued for it."""

    client_id: bytes
    address: Address
    topic: Topic
    last_heard: float
    outbox: Outbox[Outgoing] = field(default_factory=lambda: Outbox(OUTBOX_LIMIT))
    counter: PackageCounter = field(default_factory=PackageCounter)
    inbound: Reassembler = field(default_factory=Reassembler)
    inbox: asyncio.Queue[bytes] = field(default_factory=lambda: asyncio.Queue(INBOX_LIMIT))
    tasks: list[asyncio.Task[None]] = field(default_factory=list)


def _error(description: str) -> str:
    """An error reply, in the WebSocket's form."""
    return json.dumps({"status": "error", "description": description})


class _Endpoint(asyncio.DatagramProtocol):
    """asyncio's side of the socket: hands datagrams over and tracks whether it may write."""

    def __init__(self, listener: UdpFastListener) -> None:
        self._listener = listener

    def datagram_received(self, data: bytes, addr: Any) -> None:
        self._listener.received(data, (str(addr[0]), int(addr[1])))

    def error_received(self, exc: Exception) -> None:
        # An ICMP "port unreachable" from a client that went away: its timeout drops it.
        log.debug("galileo udp: %s", exc)

    def pause_writing(self) -> None:
        self._listener.writable.clear()

    def resume_writing(self) -> None:
        self._listener.writable.set()


class UdpFastListener:
    """The UDP fast server on the running event loop; :meth:`start` and :meth:`close` there.

    Args:
        ctx: the Galileo context (runtime, tokens).
        host: address to bind (loopback unless configured).
        port: UDP port; 0: any free one (see :attr:`port`).
        ping_interval: [s wall] between the server's pings to each client.
        client_timeout: [s wall] of silence after which a client is dropped.
        poll_interval: [s wall] between looks at whether a topic message is due.
    """

    def __init__(self, ctx: Context, host: str, port: int, *, ping_interval: float = 0.1,
                 client_timeout: float = 10.0, poll_interval: float = 0.01) -> None:
        if ping_interval <= 0 or client_timeout <= 0 or poll_interval <= 0:
            raise ValueError("ping_interval, client_timeout and poll_interval must be > 0")
        self._ctx = ctx
        self._host = host
        self._requested_port = port
        self._ping_interval = ping_interval
        self._timeout = client_timeout
        self._poll = poll_interval
        self._transport: asyncio.DatagramTransport | None = None
        self._clients: dict[bytes, _Client] = {}
        self._keepalive: asyncio.Task[None] | None = None
        self.writable = asyncio.Event()
        self.writable.set()

    @property
    def port(self) -> int:
        """The port actually bound."""
        assert self._transport is not None, "not started"
        return int(self._transport.get_extra_info("sockname")[1])

    @property
    def clients(self) -> int:
        """How many clients are registered."""
        return len(self._clients)

    async def start(self) -> None:
        """Bind and serve. Raises ``OSError`` when the port cannot be bound."""
        loop = asyncio.get_running_loop()
        transport, _ = await loop.create_datagram_endpoint(
            lambda: _Endpoint(self), local_addr=(self._host, self._requested_port))
        self._transport = transport
        sock = transport.get_extra_info("socket")
        if sock is not None:  # room for a client's burst of chunks (the kernel caps it)
            with contextlib.suppress(OSError):
                sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, RECEIVE_BUFFER)
        self._keepalive = asyncio.ensure_future(self._keepalive_loop())

    async def close(self) -> None:
        """Tell every client the connection is closed, stop serving and unbind."""
        tasks = [] if self._keepalive is None else [self._keepalive]
        self._keepalive = None
        for client in list(self._clients.values()):
            tasks.extend(client.tasks)
            self._drop(client, "server closing", notify=True)
        for task in tasks:
            task.cancel()
        await asyncio.gather(*tasks, return_exceptions=True)
        if self._transport is not None:
            self._transport.close()
            self._transport = None

    # --- receiving ---------------------------------------------------------------------------

    def received(self, data: bytes, address: Address) -> None:
        """One datagram from ``address``: whatever it holds, it never ends the server."""
        try:
            if not data:
                self._count("udp.empty_datagram")
                return
            if data[0] == CONNECT:
                self._register(data, address)
            elif data[0] == DATA:
                self._on_data(data, address)
            else:  # not this protocol: dropped, as the example clients drop it
                self._count("udp.unknown_frame_type")
        except Exception:  # the one broad except of the endpoint: log, keep serving
            log.error("galileo udp: datagram from %s:%d failed", *address, exc_info=True)

    def _register(self, data: bytes, address: Address) -> None:
        try:
            registration = parse_connect(data)
        except BadConnectFrame as exc:
            self._refuse(address, str(exc))
            return
        topic = TOPICS.get(registration.path)
        if topic is None:
            self._refuse(address, f"unknown topic {registration.path}")
            return
        if not self._ctx.tokens.accepts(registration.token):
            self._refuse(address, "invalid token")
            return
        if len(self._clients) >= MAX_CLIENTS:
            self._refuse(address, f"too many clients (at most {MAX_CLIENTS})")
            return
        client = _Client(self._new_id(), address, topic, time.monotonic())
        self._clients[client.client_id] = client
        client.outbox.event(connect_reply(client.client_id))  # before any message
        client.tasks.append(asyncio.ensure_future(self._write_loop(client)))
        if topic.render is not None:
            client.tasks.append(asyncio.ensure_future(self._feed_loop(client)))
        if topic.publish is not None:
            client.tasks.append(asyncio.ensure_future(self._publish_loop(client)))
        log.info("galileo udp: client %s at %s:%d on %s", client.client_id.hex(), *address,
                 topic.name)

    def _refuse(self, address: Address, reason: str) -> None:
        self._count("udp.registration_refused")
        log.info("galileo udp: registration from %s:%d refused: %s", *address, reason)
        self._send(connect_reply(None, reason), address)

    def _new_id(self) -> bytes:
        """A random id no live client has (random, so a sender cannot guess another's)."""
        while True:
            client_id = secrets.token_bytes(4)
            if client_id != bytes(4) and client_id not in self._clients:
                return client_id

    def _on_data(self, data: bytes, address: Address) -> None:
        frame = parse_data(data)
        if frame is None:
            self._count("udp.malformed_frame")
            return
        client = self._clients.get(frame.client_id)
        if client is None:
            self._count("udp.unknown_client")
            if frame.opcode != Opcode.CLOSE:  # a client of a previous run: it is not connected
                self._send(header(frame.client_id, Opcode.CLOSE), address)
            return
        if client.address != address:  # someone else using this client's id
            self._count("udp.foreign_address")
            log.debug("galileo udp: id %s from %s:%d ignored", frame.client_id.hex(), *address)
            return
        client.last_heard = time.monotonic()
        opcode = frame.opcode
        if opcode == Opcode.PING:
            client.outbox.status(header(client.client_id, Opcode.PONG), "pong")
        elif opcode == Opcode.CLOSE:
            self._drop(client, "closed by the client", notify=False)
        elif opcode == Opcode.TEXT:
            self._take_message(client, frame.payload)
        elif opcode == Opcode.BINARY:
            assert frame.package_index is not None
            try:
                message = client.inbound.feed(frame.package_index, frame.payload)
            except MessageTooLong as exc:
                self._count("udp.message_too_long")
                client.outbox.event(_error(str(exc)))
                return
            if message is not None:
                self._take_message(client, message)
        # PONG refreshed last_heard; CONTINUATION and unknown opcodes carry nothing to act on.

    def _take_message(self, client: _Client, message: bytes) -> None:
        if client.topic.publish is None:
            return  # a topic that takes no messages, as on the WebSocket
        try:
            client.inbox.put_nowait(message)
        except asyncio.QueueFull:
            self._count("udp.busy")
            client.outbox.event(_error(f"busy: more than {INBOX_LIMIT} messages waiting; "
                                       "this one was dropped"))

    # --- per-client tasks --------------------------------------------------------------------

    async def _publish_loop(self, client: _Client) -> None:
        """The client's messages, published in order of arrival."""
        publish = client.topic.publish
        assert publish is not None
        while True:
            message = await client.inbox.get()
            try:
                data = json.loads(message)
                await asyncio.to_thread(publish, self._ctx, data)
            except (ValueError, PolynavError) as exc:
                self._count("udp.bad_message")
                client.outbox.event(_error(str(exc)))
            except Exception:  # the one broad except per client: log, answer, keep serving
                log.error("galileo udp: publishing on %s failed", client.topic.name,
                          exc_info=True)
                client.outbox.event(_error("internal error"))

    async def _feed_loop(self, client: _Client) -> None:
        """The topic's messages at its rate on the runtime's clock."""
        feed = TopicFeed(self._ctx, client.topic)
        while True:
            if feed.take_due():
                text = await asyncio.to_thread(feed.render)
                if text is not None:
                    if len(text) > MAX_OUTBOUND_MESSAGE:
                        log.warning("galileo udp: %s message of %d bytes not sent (at most %d)",
                                    client.topic.name, len(text), MAX_OUTBOUND_MESSAGE)
                    else:
                        client.outbox.status(text, client.topic.name)
            await asyncio.sleep(self._poll)

    async def _write_loop(self, client: _Client) -> None:
        """Sends what the outbox holds; when it closes (not reading), drops the client."""
        while True:
            try:
                item = await client.outbox.get()
            except OutboxClosed as closed:
                self._drop(client, str(closed), notify=True)
                return
            datagrams = ((item,) if isinstance(item, bytes)
                         else message_frames(client.client_id, item, client.counter))
            for n, datagram in enumerate(datagrams, 1):
                await self.writable.wait()
                self._send(datagram, client.address)
                if n % BURST == 0:
                    await asyncio.sleep(BURST_PAUSE)

    async def _keepalive_loop(self) -> None:
        ping_key = "ping"
        while True:
            await asyncio.sleep(self._ping_interval)
            now = time.monotonic()
            for client in list(self._clients.values()):
                if now - client.last_heard > self._timeout:
                    self._drop(client, f"silent for {self._timeout:g} s", notify=True)
                else:
                    client.outbox.status(header(client.client_id, Opcode.PING), ping_key)

    # --- helpers -----------------------------------------------------------------------------

    def _count(self, name: str) -> None:
        diagnostics(self._ctx).count(name)

    def _send(self, datagram: bytes, address: Address) -> None:
        if self._transport is not None and not self._transport.is_closing():
            self._transport.sendto(datagram, address)

    def _drop(self, client: _Client, reason: str, *, notify: bool) -> None:
        """Forget ``client`` and end its tasks; with ``notify`` tell it with a CLOSE frame."""
        if self._clients.get(client.client_id) is not client:
            return
        del self._clients[client.client_id]
        client.outbox.close(reason)
        current = asyncio.current_task()
        for task in client.tasks:
            if task is not current:
                task.cancel()
        if notify:
            self._send(header(client.client_id, Opcode.CLOSE), client.address)
        log.info("galileo udp: client %s dropped: %s", client.client_id.hex(), reason)
