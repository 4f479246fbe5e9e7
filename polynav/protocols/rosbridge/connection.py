"""One rosbridge client: the ops it sends, and the frames it is sent, bounded.

The ops of rosbridge protocol v2 (``advertise``, ``unadvertise``, ``publish``, ``subscribe``,
``unsubscribe``, ``call_service``, ``set_level``, ``fragment``; ``advertise_service`` and the
ops that go with it are refused: polynav hosts no client services) are checked field by field,
and whatever is wrong is answered with a ``status`` message naming it, the connection kept open
as rosbridge keeps it. Service calls and published messages run on worker threads (their
handlers may wait for the runtime's loop); published messages in the order they came, service
calls side by side, their responses carrying the request's ``id``.

What the client is sent is bounded, never grown without limit for a client that reads slowly:
each subscription keeps at most its ``queue_length`` newest messages (its ``throttle_rate``
spaces them), responses and status messages at most ``max_replies``; a client that still does
not take what is sent within ``send_timeout`` is closed (1008) with a reason.
"""

from __future__ import annotations

import asyncio
import contextlib
import itertools
import logging
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from websockets.asyncio.server import ServerConnection
from websockets.exceptions import ConnectionClosed

from polynav.errors import PolynavError
from polynav.protocols.ros_graph import Message, RosError, Service
from polynav.protocols.rosbridge.fragments import FragmentError, Reassembly, split
from polynav.protocols.rosbridge.wire import dumps, loads

if TYPE_CHECKING:
    from polynav.protocols.rosbridge.server import RosbridgeServer

log = logging.getLogger(__name__)

#: Status levels, least severe first; a client hears the ones at or above its level.
LEVELS = ("info", "warning", "error", "none")
#: Service calls of one client that may run at once.
MAX_CALLS = 64
#: Published messages of one client that may wait for their handler.
MAX_PUBLISHES = 256


def same_type(a: str, b: str) -> bool:
    """ROS 1 and ROS 2 spell a type ``pkg/Name`` and ``pkg/msg/Name``: the same type."""
    return a.replace("/msg/", "/").replace("/srv/", "/") == b.replace("/msg/", "/").replace(
        "/srv/", "/")


@dataclass
class Subscription:
    """What one client wants of one topic (several ``subscribe`` ids share it)."""

    topic: str
    type: str
    ids: set[str | None] = field(default_factory=set)
    throttle: float = 0.0  # [s] between messages
    queue: deque[str] = field(default_factory=lambda: deque(maxlen=1))
    fragment_size: int | None = None
    last_sent: float = -1e18

    def ready(self, now: float) -> bool:
        return bool(self.queue) and now >= self.last_sent + self.throttle


class BadOp(Exception):
    """An op the connection answers with a status error (and nothing else)."""


class Connection:
    """One client of ``server`` on ``ws`` (see the module docstring)."""

    def __init__(self, server: RosbridgeServer, ws: ServerConnection) -> None:
        self._server = server
        self._ws = ws
        self._config = server.config
        self._level = LEVELS.index("error")
        self._subscriptions: dict[str, Subscription] = {}
        self._advertised: dict[str, str] = {}  # topic -> type
        self._replies: deque[str] = deque()
        self._wake = asyncio.Event()
        self._fragments = Reassembly(self._config.max_fragments, self._config.max_message_size)
        self._calls = 0
        self._publishes: asyncio.Queue[tuple[Callable[[Message], None], Message, Any]] = (
            asyncio.Queue(MAX_PUBLISHES))
        self._closing: str | None = None
        self._fragment_ids = itertools.count(1)
        self._tasks: set[asyncio.Task[None]] = set()

    # -- the connection's life -------------------------------------------------------------------

    async def run(self) -> None:
        """Serve the client until it goes or is closed."""
        writer = asyncio.ensure_future(self._write_loop())
        publisher = asyncio.ensure_future(self._publish_loop())
        try:
            async for frame in self._ws:
                if self._closing is not None:
                    break
                await self._receive(frame)
        except ConnectionClosed:
            pass
        finally:
            self._server.forget(self)
            for task in (writer, publisher, *self._tasks):
                task.cancel()
            for task in (writer, publisher, *self._tasks):
                with contextlib.suppress(asyncio.CancelledError, ConnectionClosed):
                    await task

    def deliver(self, topic: str, text: str) -> None:
        """Queue a ``publish`` frame of a subscribed topic (on the server's loop)."""
        sub = self._subscriptions.get(topic)
        if sub is None:
            return
        sub.queue.append(text)
        self._wake.set()

    @property
    def topics(self) -> set[str]:
        """The topics this client subscribes to."""
        return set(self._subscriptions)

    # -- what the client sends -------------------------------------------------------------------

    async def _receive(self, frame: str | bytes) -> None:
        if isinstance(frame, bytes):
            # rosbridge takes CBOR/BSON in binary frames; polynav speaks JSON only.
            self._status("error", "binary frames are not accepted: send JSON text")
            return
        try:
            data = loads(frame)
        except ValueError as exc:
            self._status("error", f"{exc}")
            return
        await self._dispatch(data)

    async def _dispatch(self, data: Any) -> None:
        ident = data.get("id") if isinstance(data, dict) else None
        ident = ident if isinstance(ident, (str, int)) and not isinstance(ident, bool) else None
        try:
            if not isinstance(data, dict):
                raise BadOp("a message must be a JSON object with an 'op'")
            op = data.get("op")
            if not isinstance(op, str):
                raise BadOp("missing or non-string 'op'")
            handler = self._OPS.get(op)
            if handler is None:
                raise BadOp(f"unknown op {op!r}")
            await handler(self, data, ident)
        except BadOp as exc:
            self._status("error", str(exc), ident)

    async def _advertise(self, data: dict[str, Any], ident: Any) -> None:
        topic, kind = _topic(data), _field(data, "type", str)
        wanted = self._server.graph.subscription(topic)
        if wanted is not None and not same_type(wanted.type, kind):
            raise BadOp(f"{topic} is of type {wanted.type}, not {kind}")
        if topic in self._advertised and not same_type(self._advertised[topic], kind):
            raise BadOp(f"{topic} is advertised as {self._advertised[topic]} already")
        self._advertised[topic] = kind
        if wanted is None:
            self._status("warning", f"no one takes {topic} on this robot: messages published "
                                    "there go nowhere", ident)

    async def _unadvertise(self, data: dict[str, Any], ident: Any) -> None:
        topic = _topic(data)
        if self._advertised.pop(topic, None) is None:
            self._status("warning", f"{topic} was not advertised", ident)

    async def _publish(self, data: dict[str, Any], ident: Any) -> None:
        topic = _topic(data)
        msg = data.get("msg")
        if not isinstance(msg, dict):
            raise BadOp(f"publish to {topic}: 'msg' must be a JSON object")
        wanted = self._server.graph.subscription(topic)
        kind = self._advertised.get(topic)
        if kind is None:
            if wanted is None:
                raise BadOp(f"cannot infer topic type for topic {topic} as it is not yet "
                            "advertised")
            self._advertised[topic] = kind = wanted.type  # rosbridge advertises it on the way
        if wanted is None:
            return  # advertised by the client, taken by no one: ROS drops it the same way
        try:
            self._publishes.put_nowait((wanted.handle, msg, ident))
        except asyncio.QueueFull:
            raise BadOp(f"publish to {topic}: {MAX_PUBLISHES} messages wait already; "
                        "this one is dropped") from None

    async def _subscribe(self, data: dict[str, Any], ident: Any) -> None:
        topic = _topic(data)
        kind = _optional(data, "type", str)
        throttle = _optional(data, "throttle_rate", int)
        queue_length = _optional(data, "queue_length", int)
        fragment_size = _optional(data, "fragment_size", int)
        compression = _optional(data, "compression", str)
        for name, value in (("throttle_rate", throttle), ("queue_length", queue_length)):
            if value is not None and value < 0:
                raise BadOp(f"subscribe to {topic}: '{name}' must be >= 0")
        if fragment_size is not None and fragment_size < 1:
            raise BadOp(f"subscribe to {topic}: 'fragment_size' must be >= 1")
        declared = self._server.graph.topic(topic)
        if declared is None:
            if kind is None:
                raise BadOp(f"cannot infer topic type for topic {topic} as it is not yet "
                            "advertised")
            self._status("warning", f"{topic} is not published on this robot (yet)", ident)
        elif kind is not None and not same_type(declared.type, kind):
            raise BadOp(f"{topic} is of type {declared.type}, not {kind}")
        if compression not in (None, "none"):
            self._status("warning", f"compression {compression!r} is not offered: {topic} is "
                                    "sent as JSON", ident)
        limit = self._config.max_queue_length
        depth = min(limit, max(1, queue_length or 1))
        sub = self._subscriptions.get(topic)
        if sub is None:
            sub = self._subscriptions[topic] = Subscription(
                topic, declared.type if declared is not None else str(kind))
        sub.ids.add(None if ident is None else str(ident))
        sub.throttle = (throttle or 0) / 1000.0
        if sub.queue.maxlen != depth:
            sub.queue = deque(sub.queue, maxlen=depth)
        sub.fragment_size = fragment_size
        self._server.subscribed(self, topic)

    async def _unsubscribe(self, data: dict[str, Any], ident: Any) -> None:
        topic = _topic(data)
        sub = self._subscriptions.get(topic)
        if sub is None:
            self._status("warning", f"not subscribed to {topic}", ident)
            return
        sub.ids.discard(None if ident is None else str(ident))
        if ident is None or not sub.ids:
            del self._subscriptions[topic]
            self._server.unsubscribed(self, topic)

    async def _call_service(self, data: dict[str, Any], ident: Any) -> None:
        name = _field(data, "service", str)
        args = data.get("args", {})
        if isinstance(args, list) and not args:
            args = {}
        fragment_size = _optional(data, "fragment_size", int)
        if not isinstance(args, dict):
            self._respond(name, ident, False, "'args' must be a JSON object", fragment_size)
            return
        service = self._server.service(name)
        if service is None:
            self._respond(name, ident, False, f"Service {name} does not exist", fragment_size)
            return
        if self._calls >= MAX_CALLS:
            self._respond(name, ident, False, f"{MAX_CALLS} calls are running already; call "
                          "again when one has answered", fragment_size)
            return
        self._calls += 1
        task = asyncio.ensure_future(self._run_call(service, args, ident, fragment_size))
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)

    async def _refuse_service_ops(self, data: dict[str, Any], ident: Any) -> None:
        raise BadOp(f"{data['op']}: polynav hosts no services for clients; call the robot's "
                    "services with call_service")

    async def _set_level(self, data: dict[str, Any], ident: Any) -> None:
        level = data.get("level")
        if level not in LEVELS:
            raise BadOp(f"set_level: 'level' must be one of {', '.join(LEVELS)}")
        self._level = LEVELS.index(level)

    async def _fragment(self, data: dict[str, Any], ident: Any) -> None:
        try:
            whole = self._fragments.add(data)
        except FragmentError as exc:
            raise BadOp(str(exc)) from None
        if whole is None:
            return
        try:
            inner = loads(whole)
        except ValueError as exc:
            raise BadOp(f"fragment {data.get('id')}: {exc}") from None
        if isinstance(inner, dict) and inner.get("op") == "fragment":
            raise BadOp("a fragment may not hold another fragment")
        await self._dispatch(inner)

    async def _refuse_png(self, data: dict[str, Any], ident: Any) -> None:
        raise BadOp("png: compressed frames are not accepted: send JSON text")

    async def _auth(self, data: dict[str, Any], ident: Any) -> None:
        """rosbridge's ``auth`` (rosauth MAC): polynav's rosbridge is open like rosbridge
        without ``authenticate:=true``, so it is taken and ignored."""

    _OPS: dict[str, Callable[[Connection, dict[str, Any], Any], Any]] = {
        "advertise": _advertise, "unadvertise": _unadvertise, "publish": _publish,
        "subscribe": _subscribe, "unsubscribe": _unsubscribe, "call_service": _call_service,
        "advertise_service": _refuse_service_ops, "unadvertise_service": _refuse_service_ops,
        "service_response": _refuse_service_ops, "set_level": _set_level,
        "fragment": _fragment, "png": _refuse_png, "auth": _auth,
    }

    # -- running handlers ------------------------------------------------------------------------

    async def _run_call(self, service: Service, args: Message, ident: Any,
                        fragment_size: int | None) -> None:
        try:
            values = await asyncio.to_thread(service.call, args)
        except (RosError, PolynavError, ValueError, KeyError, TypeError) as exc:
            self._respond(service.name, ident, False, _reason(exc), fragment_size)
        except Exception as exc:  # a handler's fault: answered, logged, the server goes on
            log.exception("rosbridge: service %s failed", service.name)
            self._respond(service.name, ident, False, f"internal error: {exc}", fragment_size)
        else:
            self._respond(service.name, ident, True, values, fragment_size)
        finally:
            self._calls -= 1

    async def _publish_loop(self) -> None:
        while True:
            handle, msg, ident = await self._publishes.get()
            try:
                await asyncio.to_thread(handle, msg)
            except (RosError, PolynavError, ValueError, KeyError, TypeError) as exc:
                self._status("error", _reason(exc), ident)
            except Exception as exc:  # a handler's fault: told, logged, the server goes on
                log.exception("rosbridge: a published message failed")
                self._status("error", f"internal error: {exc}", ident)

    # -- what the client is sent -----------------------------------------------------------------

    def _respond(self, service: str, ident: Any, result: bool, values: Any,
                 fragment_size: int | None) -> None:
        frame: dict[str, Any] = {"op": "service_response", "service": service}
        if ident is not None:
            frame["id"] = ident
        frame["values"] = values
        frame["result"] = result
        self._reply(dumps(frame), fragment_size)

    def _status(self, level: str, msg: str, ident: Any = None) -> None:
        if LEVELS.index(level) < self._level:
            return
        frame: dict[str, Any] = {"op": "status", "level": level, "msg": msg}
        if ident is not None:
            frame["id"] = ident
        self._reply(dumps(frame), None)

    def _reply(self, text: str, fragment_size: int | None) -> None:
        frames = [text] if fragment_size is None or len(text) <= fragment_size else [
            dumps(f) for f in split(text, fragment_size, f"reply_{next(self._fragment_ids)}")]
        if len(self._replies) + len(frames) > self._config.max_replies:
            self._close_slow(f"{self._config.max_replies} replies wait unread")
            return
        self._replies.extend(frames)
        self._wake.set()

    def _next_frames(self, now: float) -> tuple[list[str], float | None]:
        """The next frames to send, or none and how long until a throttled one is due."""
        if self._replies:
            return [self._replies.popleft()], None
        wait: float | None = None
        for sub in self._subscriptions.values():
            if sub.ready(now):
                text = sub.queue.popleft()
                sub.last_sent = now
                if sub.fragment_size is not None and len(text) > sub.fragment_size:
                    ident = f"{sub.topic}_{next(self._fragment_ids)}"
                    return [dumps(f) for f in split(text, sub.fragment_size, ident)], None
                return [text], None
            if sub.queue:
                due = sub.last_sent + sub.throttle - now
                wait = due if wait is None else min(wait, due)
        return [], wait

    async def _write_loop(self) -> None:
        while self._closing is None:
            frames, wait = self._next_frames(time.monotonic())
            if not frames:
                self._wake.clear()
                with contextlib.suppress(TimeoutError):
                    await asyncio.wait_for(self._wake.wait(), wait)
                continue
            for text in frames:
                try:
                    await asyncio.wait_for(self._ws.send(text), self._config.send_timeout)
                except TimeoutError:
                    timeout = self._config.send_timeout
                    self._close_slow(f"a frame was not taken within {timeout:g} s")
                    return
            # Let the reader and the other connections run between frames of a busy stream.
            await asyncio.sleep(0)

    def _close_slow(self, reason: str) -> None:
        if self._closing is not None:
            return
        self._closing = reason
        log.warning("rosbridge: closing a client that does not read: %s", reason)
        task = asyncio.ensure_future(_close(self._ws, f"not reading: {reason}"))
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)


async def _close(ws: ServerConnection, reason: str) -> None:
    with contextlib.suppress(Exception):
        # A client that does not read may not answer the close handshake either: bounded.
        await asyncio.wait_for(ws.close(1008, reason[:120]), 5.0)
    ws.transport.abort()


def _reason(exc: BaseException) -> str:
    return str(exc) if str(exc) else type(exc).__name__


def _topic(data: dict[str, Any]) -> str:
    topic: str = _field(data, "topic", str)
    return topic


def _field(data: dict[str, Any], key: str, kind: type) -> Any:
    value = data.get(key)
    if value is None:
        raise BadOp(f"{data.get('op')}: missing '{key}'")
    if not isinstance(value, kind) or (kind is int and isinstance(value, bool)):
        raise BadOp(f"{data.get('op')}: '{key}' must be a {_KIND_NAMES.get(kind, kind.__name__)}")
    if kind is str and not value:
        raise BadOp(f"{data.get('op')}: '{key}' must not be empty")
    return value


def _optional(data: dict[str, Any], key: str, kind: type) -> Any:
    return None if data.get(key) is None else _field(data, key, kind)


_KIND_NAMES = {str: "string", int: "integer"}
