"""The Yunji TCP server: accept, read, decode, dispatch, write (STYLE R4: transport only).

Each client has a reader task and a writer task joined by an ``Outbox``
(:mod:`polynav.protocols.outbox`): a command's reply is written before the notifications it
causes, stream callbacks are coalesced to the newest per topic when the client lags, and a
client that stops reading lets notifications pile up to ``queue_size`` and is then
disconnected, so it can never hold up the others (or the runtime). Requests of one client are
answered in order; each runs its handler on a worker thread (runtime commands wait for the
runtime's loop). The one broad ``except`` per request logs with ``exc_info`` and answers
``UNKNOWN_ERROR``, keeping the connection.

Framing (see :mod:`polynav.protocols.yunji.codec`): a read that leaves an undelimited command in
the buffer completes it (bare commands, one per ``send()``) until the client has sent a newline
once; from then on the connection is newline-framed and a partial command waits for the rest.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
from dataclasses import dataclass

import polynav
from polynav.errors import ConfigError, PolynavError
from polynav.listen import tcp_listener
from polynav.protocols.http_listener import HttpListener
from polynav.protocols.outbox import Outbox
from polynav.protocols.server_thread import ServerThread
from polynav.protocols.yunji import codec, context, errors, routes, streams
from polynav.protocols.yunji.events import NotificationMapper
from polynav.protocols.yunji.http import create_app
from polynav.protocols.yunji.messages import Reply, Status, StreamRequest
from polynav.runtime.robot_runtime import RobotRuntime

log = logging.getLogger(__name__)

_READ_SIZE = 65536
_DIRECT_WRITE_LIMIT = 65536  # [bytes] buffered in the transport before writes go via the task


@dataclass(frozen=True, slots=True)
class YunjiConfig:
    """Where the Yunji server listens and how much it buffers.

    Attributes:
        host: interface to bind; loopback unless configured (a robot would use 0.0.0.0).
        port: TCP port, 31001 as on the Yunji chassis; 0 lets the OS choose (tests).
        max_command_bytes: the longest command; longer without a delimiter closes the
            connection.
        queue_size: replies and notifications queued unsent per client before it is dropped as
            not reading (callbacks are coalesced per topic and do not count).
        product_id: what ``/api/robot_info`` reports.
        stream_poll_interval: how often [s wall] a ``request_data`` stream looks whether a
            callback is due on the runtime's (simulated) clock.
        prepare_navigation: start navigation on the current floor's map at start-up when the
            runtime is FREE (a Yunji robot is always ready to move).
        http_port: also serve the legacy HTTP form on this port (8808 on the robot; 0: any;
            ``None``: not at all), on the same host.
    """

    host: str = "127.0.0.1"
    port: int = 31001
    max_command_bytes: int = codec.DEFAULT_MAX_COMMAND_BYTES
    queue_size: int = 256
    product_id: str = "WATER-POLYNAV-SIM00001"
    prepare_navigation: bool = True
    stream_poll_interval: float = 0.01
    http_port: int | None = None

    def __post_init__(self) -> None:
        if not self.host:
            raise ConfigError("yunji.host", "must not be empty")
        if not 0 <= self.port <= 65535:
            raise ConfigError("yunji.port", f"must be in [0, 65535], got {self.port}")
        if self.http_port is not None and not 0 <= self.http_port <= 65535:
            raise ConfigError("yunji.http_port", f"must be in [0, 65535], got {self.http_port}")
        if not 64 <= self.max_command_bytes <= 1_048_576:
            raise ConfigError(
                "yunji.max_command_bytes", f"must be in [64, 1048576], got {self.max_command_bytes}"
            )
        if not 0.0 < self.stream_poll_interval <= 1.0:
            raise ConfigError(
                "yunji.stream_poll_interval",
                f"must be in (0, 1] s, got {self.stream_poll_interval}",
            )
        if not 1 <= self.queue_size <= 100_000:
            raise ConfigError("yunji.queue_size", f"must be in [1, 100000], got {self.queue_size}")


class _Client:
    """One connection: its outbox (replies first, bounded) and writer task."""

    def __init__(self, writer: asyncio.StreamWriter, queue_size: int) -> None:
        self.writer = writer
        self.outbox: Outbox[bytes] = Outbox(limit=queue_size)
        self.closed = False
        self.peer = writer.get_extra_info("peername")
        self.streams: dict[str, asyncio.Task[None]] = {}
        self._backed_up = asyncio.Event()

    def begin_command(self) -> None:
        self.outbox.begin_command()

    def reply(self, packet: bytes) -> None:
        self.outbox.reply(packet)
        self._check()
        self._write_now()

    def notify(self, packet: bytes) -> None:
        self.outbox.event(packet)
        self._check()
        self._write_now()

    def callback(self, topic: str, packet: bytes) -> None:
        self.outbox.status(packet, key=topic)
        self._write_now()

    def _write_now(self) -> None:
        """Write what is ready while the transport is not backed up; once it is, wake the
        writer task, which waits on ``drain`` and goes on. The task sleeps otherwise: waking it
        for every reply would cost a task switch per command."""
        transport = self.writer.transport
        while not self.closed:
            if transport.get_write_buffer_size() >= _DIRECT_WRITE_LIMIT:
                self._backed_up.set()
                return
            packet = self.outbox.get_nowait()
            if packet is None:
                return
            self.writer.write(packet)

    def _check(self) -> None:
        """An outbox closed for not reading: drop the connection and its unsent data."""
        if self.outbox.closed and not self.closed:
            log.warning("yunji: client %s: %s, disconnecting", self.peer,
                        self.outbox.closed_reason)
            self.close(abort=True)

    def close(self, *, abort: bool = False) -> None:
        """Close the connection; ``abort`` drops unsent data (a client that does not read
        would otherwise hold the connection open until its buffered data drained)."""
        if not self.closed:
            self.closed = True
            self._backed_up.set()  # the writer task ends
            self.outbox.close("connection closed")
            if abort:
                self.writer.transport.abort()
            else:
                self.writer.close()

    async def write_loop(self) -> None:
        """Drain a backed-up transport, then write what waited meanwhile."""
        try:
            while not self.closed:
                await self._backed_up.wait()
                self._backed_up.clear()
                await self.writer.drain()
                self._write_now()
        except (ConnectionError, OSError) as exc:
            log.info("yunji: client %s write failed: %s", self.peer, exc)
        finally:
            self.close()


class YunjiServer:
    """A listening Yunji server; build it with :func:`serve`."""

    def __init__(self, runtime: RobotRuntime, config: YunjiConfig) -> None:
        self.config = config
        self._ctx = context.Context(
            runtime=runtime, product_id=config.product_id, version=polynav.__version__
        )
        self._server: asyncio.Server | None = None
        self._clients: set[_Client] = set()
        self._tasks: set[asyncio.Task[None]] = set()
        self._pump: asyncio.Task[None] | None = None
        self._http: HttpListener | None = None

    @property
    def http_port(self) -> int | None:
        """The HTTP listener's port, if it serves."""
        return None if self._http is None else self._http.port

    @property
    def port(self) -> int:
        """The port actually bound (useful with port 0)."""
        assert self._server is not None
        return int(self._server.sockets[0].getsockname()[1])

    @property
    def client_count(self) -> int:
        return len(self._clients)

    async def start(self) -> None:
        if self.config.prepare_navigation:
            await asyncio.to_thread(context.prepare, self._ctx.runtime)
        self._server = await asyncio.start_server(
            self._handle, sock=tcp_listener(self.config.host, self.config.port), limit=_READ_SIZE
        )
        self._pump = asyncio.ensure_future(self._notify())
        log.info("yunji: listening on %s:%d", self.config.host, self.port)
        if self.config.http_port is not None:
            http = HttpListener(
                create_app(self._answer, self.config.max_command_bytes), self.config.host,
                self.config.http_port, name="Yunji HTTP",
            )
            try:
                await http.start()
            except OSError:
                await self.close()
                raise
            self._http = http
            log.info("yunji: HTTP on %s:%d", self.config.host, http.port)

    async def _notify(self) -> None:
        """Broadcast the notifications of the runtime's events until closed."""
        runtime = self._ctx.runtime
        snapshot = runtime.status()
        mapper = NotificationMapper(
            self._ctx.target_of, snapshot.estop_hardware or snapshot.estop_software
        )
        subscription = runtime.bus.subscribe()
        try:
            while True:
                batch = await subscription.get()
                if not batch and subscription.closed:
                    return
                for event in batch:
                    try:
                        notes = mapper.map(event)
                    except Exception:  # one bad event must not end the notifications
                        log.error("yunji: cannot map %r", event, exc_info=True)
                        continue
                    for note in notes:
                        self.broadcast(
                            codec.encode_notification(
                                note.code, note.level, note.description, note.data
                            )
                        )
        finally:
            runtime.bus.unsubscribe(subscription)

    def broadcast(self, packet: bytes) -> None:
        """Send ``packet`` (a notification) to every connected client, after the reply of any
        command that client has in flight."""
        for client in list(self._clients):
            client.notify(packet)

    async def close(self) -> None:
        """Stop listening and drop every client."""
        if self._http is not None:
            await self._http.close()
            self._http = None
        if self._server is not None:
            self._server.close()
        if self._pump is not None:
            self._pump.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await self._pump
        for client in list(self._clients):
            client.close(abort=True)
        for task in list(self._tasks):
            task.cancel()
        for task in list(self._tasks):
            with contextlib.suppress(asyncio.CancelledError, Exception):
                await task
        if self._server is not None:
            await self._server.wait_closed()

    async def _handle(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        client = _Client(writer, self.config.queue_size)
        self._clients.add(client)
        writer_task = asyncio.ensure_future(client.write_loop())
        self._tasks.add(writer_task)
        try:
            await self._read_loop(client, reader)
        except (ConnectionError, OSError) as exc:
            log.info("yunji: client %s read failed: %s", client.peer, exc)
        finally:
            self._clients.discard(client)
            client.close()
            for task in client.streams.values():
                task.cancel()
            writer_task.cancel()
            with contextlib.suppress(asyncio.CancelledError, ConnectionError, OSError):
                await writer_task
            self._tasks.discard(writer_task)

    async def _read_loop(self, client: _Client, reader: asyncio.StreamReader) -> None:
        buf = b""
        newline_framed = False
        max_bytes = self.config.max_command_bytes
        while not client.closed:
            data = await reader.read(_READ_SIZE)
            if not data:
                return
            if b"\n" in data:
                newline_framed = True
            buf += data
            while buf and not client.closed:
                try:
                    used, command = codec.decode(
                        buf, end_of_read=not newline_framed, max_bytes=max_bytes
                    )
                except codec.FrameTooLong as exc:
                    log.warning("yunji: client %s: %s; closing", client.peer, exc)
                    # Written past the queue: the connection ends here anyway.
                    client.writer.write(
                        codec.encode_reply("", "", Status.INVALID_REQUEST.value, str(exc))
                    )
                    client.close()
                    return
                except codec.MalformedCommand as exc:
                    buf = buf[exc.used :]
                    client.reply(
                        codec.encode_reply(
                            exc.path, exc.uuid, Status.INVALID_REQUEST.value, str(exc)
                        )
                    )
                    continue
                buf = buf[used:]
                if command is None:
                    break
                client.begin_command()
                packet, reply = await self._answer(command)
                client.reply(packet)
                if reply.stream is not None:
                    self._subscribe(client, reply.stream)

    def _subscribe(self, client: _Client, request: StreamRequest) -> None:
        old = client.streams.pop(request.topic, None)
        if old is not None:
            old.cancel()
        if request.on and not client.closed:
            client.streams[request.topic] = asyncio.ensure_future(
                self._stream(client, request.topic, request.frequency)
            )

    async def _stream(self, client: _Client, topic: str, frequency: float) -> None:
        """Send ``topic`` every ``1/frequency`` s of the runtime's clock (at most one catch-up
        packet when the clock jumped)."""
        runtime = self._ctx.runtime
        period = 1.0 / frequency
        due = runtime.now()
        while not client.closed:
            now = runtime.now()
            if now + 1e-9 >= due:
                try:
                    results = await asyncio.to_thread(streams.stream_results, self._ctx, topic)
                except PolynavError as exc:  # the robot cannot tell now (powered off): skip
                    log.debug("yunji: no %s callback: %s", topic, exc)
                except Exception:  # the stream's broad except: log, keep streaming
                    log.error("yunji: %s stream failed", topic, exc_info=True)
                else:
                    if streams.still_current(self._ctx, topic):
                        client.callback(topic, codec.encode_callback(topic, results))
                due = max(due + period, now)
            await asyncio.sleep(self.config.stream_poll_interval)

    async def _answer(self, command: codec.Command) -> tuple[bytes, Reply]:
        handler = routes.HANDLERS.get(command.path)
        if handler is None:
            reply = Reply(Status.INVALID_REQUEST, f"unknown command {command.path}")
        else:
            try:
                if command.path in routes.SNAPSHOT_READS:
                    reply = handler(self._ctx, command.params)
                else:
                    reply = await asyncio.to_thread(handler, self._ctx, command.params)
                packet = _encode(command, reply)
            except Exception as exc:  # the one broad except per request (STYLE R4)
                status, message = errors.status_for(exc)
                if status is Status.UNKNOWN_ERROR:
                    log.error("yunji: %s failed", command.raw, exc_info=True)
                reply = Reply(status, message)
            else:
                return packet, reply
        return _encode(command, reply), reply


def _encode(command: codec.Command, reply: Reply) -> bytes:
    return codec.encode_reply(
        command.path,
        command.uuid,
        reply.status.value,
        reply.error_message,
        reply.results,
        task_id=reply.task_id,
    )


async def serve(runtime: RobotRuntime, config: YunjiConfig | None = None) -> YunjiServer:
    """Start a Yunji server for ``runtime`` on the running event loop; returns it listening.

    Close it with ``await server.close()``.
    """
    server = YunjiServer(runtime, config or YunjiConfig())
    await server.start()
    return server


class YunjiThread(ServerThread[YunjiServer]):
    """A Yunji server on its own event loop in a daemon thread, beside another server's loop
    (``polynav run`` serves the native API with uvicorn on the main thread)."""

    def __init__(self, runtime: RobotRuntime, config: YunjiConfig) -> None:
        super().__init__("polynav-yunji", lambda: serve(runtime, config))

    @property
    def port(self) -> int:
        return self.server.port

    @property
    def http_port(self) -> int | None:
        return self.server.http_port
