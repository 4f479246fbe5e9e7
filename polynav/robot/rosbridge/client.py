"""A rosbridge v2 client that keeps its connection: subscribe, advertise, publish, call.

It runs an asyncio loop on a daemon thread. Subscriptions and advertisements are remembered and
made again after every reconnect; messages are handed to their callbacks on the client's
thread. A dropped connection (closed, refused, or silent for ``silence_timeout``) is tried
again with a doubling backoff; while it is away, :meth:`publish` drops what it is given (the
robot's driver stops on its own command timeout) and :meth:`call` fails at once.
"""

from __future__ import annotations

import asyncio
import contextlib
import itertools
import json
import logging
import threading
import time
from collections.abc import Callable
from concurrent.futures import Future
from dataclasses import dataclass
from typing import Any

from websockets.asyncio.client import ClientConnection, connect
from websockets.exceptions import ConnectionClosed, InvalidURI

log = logging.getLogger(__name__)

Callback = Callable[[dict[str, Any]], None]

#: The largest message taken from the robot (a map can be large) [bytes].
MAX_MESSAGE = 64 * 1024 * 1024


class BridgeError(Exception):
    """A call that cannot be made or that the robot answered with ``result: false``."""


@dataclass
class _Subscription:
    topic: str
    type: str
    callback: Callback
    throttle_rate: int = 0
    queue_length: int = 1


class RosbridgeClient:
    """A connection to ``url`` kept up (see the module docstring).

    Args:
        url: ``ws://HOST:PORT``.
        reconnect_min, reconnect_max: backoff bounds [s].
        silence_timeout: no message for this long [s] drops the connection.
        on_state: called (on the client's thread) with ``True``/``False`` as the connection
            comes and goes.
    """

    def __init__(self, url: str, *, reconnect_min: float = 0.2, reconnect_max: float = 5.0,
                 silence_timeout: float = 3.0,
                 on_state: Callable[[bool], None] | None = None) -> None:
        self.url = url
        self._reconnect = (reconnect_min, reconnect_max)
        self._silence = silence_timeout
        self._on_state = on_state
        self._subscriptions: dict[str, _Subscription] = {}
        self._advertised: dict[str, str] = {}
        self._pending: dict[str, Future[Any]] = {}
        self._fragments: dict[str, dict[int, str]] = {}
        self._ids = itertools.count(1)
        self._ws: ClientConnection | None = None
        self._loop = asyncio.new_event_loop()
        self._stopping = False
        self.connects = 0
        self.last_message = 0.0
        self._thread = threading.Thread(target=self._run, name="polynav-rosbridge-client",
                                        daemon=True)
        self._thread.start()

    # -- state ------------------------------------------------------------------------------------

    @property
    def connected(self) -> bool:
        return self._ws is not None

    def close(self) -> None:
        """Close the connection and end the thread."""
        self._stopping = True

        async def stop() -> None:
            if self._ws is not None:
                await self._ws.close()
            for task in asyncio.all_tasks():
                if task is not asyncio.current_task():
                    task.cancel()

        with contextlib.suppress(RuntimeError):
            asyncio.run_coroutine_threadsafe(stop(), self._loop).result(timeout=5)
        self._thread.join(timeout=5)

    # -- what the robot is asked -------------------------------------------------------------------

    def subscribe(self, topic: str, type_: str, callback: Callback, *, throttle_rate: int = 0,
                  queue_length: int = 1) -> None:
        """Receive ``topic`` (now and after every reconnect)."""
        sub = _Subscription(topic, type_, callback, throttle_rate, queue_length)
        self._subscriptions[topic] = sub
        self._send_soon(self._subscribe_frame(sub))

    def advertise(self, topic: str, type_: str) -> None:
        """Say this client publishes ``topic`` (now and after every reconnect)."""
        self._advertised[topic] = type_
        self._send_soon({"op": "advertise", "topic": topic, "type": type_})

    def publish(self, topic: str, msg: dict[str, Any]) -> bool:
        """Send ``msg`` on ``topic`` (any thread); ``False`` when not connected (dropped)."""
        if self._ws is None:
            return False
        self._send_soon({"op": "publish", "topic": topic, "msg": msg})
        return True

    def call(self, service: str, args: dict[str, Any] | None = None,
             timeout: float = 5.0) -> Any:
        """Call ``service`` and wait for its values.

        Raises:
            BridgeError: not connected, no answer in time, or ``result: false``.
        """
        if self._ws is None:
            raise BridgeError(f"{service}: not connected to {self.url}")
        ident = f"polynav_call_{next(self._ids)}"
        future: Future[Any] = Future()
        self._pending[ident] = future
        self._send_soon({"op": "call_service", "id": ident, "service": service,
                         "args": args or {}})
        try:
            return future.result(timeout)
        except TimeoutError as exc:
            raise BridgeError(f"{service}: no answer within {timeout:g} s") from exc
        finally:
            self._pending.pop(ident, None)

    # -- the client's thread ----------------------------------------------------------------

    def _send_soon(self, frame: dict[str, Any]) -> None:
        text = json.dumps(frame)

        def send() -> None:
            ws = self._ws
            if ws is not None:
                task = asyncio.ensure_future(_send(ws, text))
                task.add_done_callback(_quiet)

        with contextlib.suppress(RuntimeError):  # the loop has closed
            self._loop.call_soon_threadsafe(send)

    @staticmethod
    def _subscribe_frame(sub: _Subscription) -> dict[str, Any]:
        return {"op": "subscribe", "id": f"polynav_sub_{sub.topic}", "topic": sub.topic,
                "type": sub.type, "throttle_rate": sub.throttle_rate,
                "queue_length": sub.queue_length}

    def _run(self) -> None:
        asyncio.set_event_loop(self._loop)
        with contextlib.suppress(asyncio.CancelledError):
            self._loop.run_until_complete(self._keep_connected())
        self._loop.close()

    async def _keep_connected(self) -> None:
        delay = self._reconnect[0]
        while not self._stopping:
            try:
                async with connect(self.url, max_size=MAX_MESSAGE, open_timeout=5,
                                   ping_interval=None, compression=None) as ws:
                    delay = self._reconnect[0]
                    await self._serve(ws)
            except (OSError, ConnectionClosed, TimeoutError, InvalidURI) as exc:
                if not self._stopping:
                    log.debug("rosbridge client: %s: %s", self.url, exc)
            except Exception:  # a peer speaking another protocol: logged, tried again
                log.warning("rosbridge client: %s failed", self.url, exc_info=True)
            finally:
                self._set_disconnected()
            if self._stopping:
                return
            await asyncio.sleep(delay)
            delay = min(self._reconnect[1], delay * 2.0)

    async def _serve(self, ws: ClientConnection) -> None:
        # Connected first, then everything remembered: a subscribe made meanwhile is sent by
        # its own call or by this (twice is harmless: the same id), never lost between them.
        self._ws = ws
        for topic, type_ in list(self._advertised.items()):
            await ws.send(json.dumps({"op": "advertise", "topic": topic, "type": type_}))
        for sub in list(self._subscriptions.values()):
            await ws.send(json.dumps(self._subscribe_frame(sub)))
        self.connects += 1
        self.last_message = time.monotonic()
        log.info("rosbridge client: connected to %s (%d)", self.url, self.connects)
        if self._on_state is not None:
            self._on_state(True)
        while True:
            try:
                frame = await asyncio.wait_for(ws.recv(), self._silence)
            except TimeoutError:
                log.warning("rosbridge client: %s silent for %g s; reconnecting", self.url,
                            self._silence)
                return
            self.last_message = time.monotonic()
            self._receive(frame)

    def _set_disconnected(self) -> None:
        was = self._ws is not None
        self._ws = None
        for future in list(self._pending.values()):
            if not future.done():
                future.set_exception(BridgeError(f"the connection to {self.url} dropped"))
        if was:
            log.warning("rosbridge client: disconnected from %s", self.url)
            if self._on_state is not None:
                self._on_state(False)

    def _receive(self, frame: str | bytes) -> None:
        try:
            data = json.loads(frame)
        except ValueError:
            log.warning("rosbridge client: invalid JSON from %s dropped", self.url)
            return
        if not isinstance(data, dict):
            return
        op = data.get("op")
        if op == "fragment":
            whole = self._fragment(data)
            if whole is not None:
                self._receive(whole)
        elif op == "publish":
            sub = self._subscriptions.get(str(data.get("topic")))
            msg = data.get("msg")
            if sub is not None and isinstance(msg, dict):
                try:
                    sub.callback(msg)
                except Exception:  # a bad message of the robot's: dropped, logged
                    log.warning("rosbridge client: a %s message was dropped", sub.topic,
                                exc_info=True)
        elif op == "service_response":
            future = self._pending.get(str(data.get("id")))
            if future is not None and not future.done():
                if data.get("result", True):
                    future.set_result(data.get("values"))
                else:
                    future.set_exception(BridgeError(str(data.get("values"))))
        elif op == "status":
            log.info("rosbridge client: %s says %s: %s", self.url, data.get("level"),
                     data.get("msg"))

    def _fragment(self, data: dict[str, Any]) -> str | None:
        ident, num, total, piece = (data.get(k) for k in ("id", "num", "total", "data"))
        if not isinstance(num, int) or not isinstance(total, int) or not isinstance(piece, str):
            return None
        key = str(ident)
        pieces = self._fragments.setdefault(key, {})
        if len(self._fragments) > 16:  # bounded: forget the oldest half-received one
            self._fragments.pop(next(iter(self._fragments)))
        pieces[num] = piece
        if len(pieces) < total:
            return None
        self._fragments.pop(key, None)
        return "".join(pieces.get(i, "") for i in range(total))


async def _send(ws: ClientConnection, text: str) -> None:
    with contextlib.suppress(ConnectionClosed):
        await ws.send(text)


def _quiet(task: asyncio.Task[None]) -> None:
    if not task.cancelled():
        task.exception()
