"""The event bus: runtime events fanned out to subscribers that read at their own pace.

The runtime's tick loop publishes; adapters (the WebSocket, vendor dialects) subscribe. A slow or
stuck subscriber must never hold the robot up, so each subscription is a bounded queue: publish
only appends (under a lock held for a few instructions) and, when the queue is full, drops the
oldest event and counts it in :attr:`Subscription.dropped`. A subscriber reads batches with
:meth:`Subscription.get_nowait`, blocks a thread with :meth:`Subscription.wait`, or awaits
:meth:`Subscription.get` from an asyncio loop (woken with ``call_soon_threadsafe``).
"""

from __future__ import annotations

import asyncio
import logging
import threading
from collections import deque

from polynav.errors import InvalidRequest
from polynav.runtime.events import RuntimeEvent

log = logging.getLogger(__name__)


class Subscription:
    """One subscriber's bounded queue of events, oldest first."""

    def __init__(self, maxlen: int) -> None:
        if maxlen < 1:
            raise InvalidRequest("maxlen", f"must be >= 1, got {maxlen}")
        self.maxlen = maxlen
        self._queue: deque[RuntimeEvent] = deque()
        self._cond = threading.Condition(threading.Lock())
        self._async_waiters: list[tuple[asyncio.AbstractEventLoop, asyncio.Future[None]]] = []
        self._dropped = 0
        self._closed = False

    @property
    def dropped(self) -> int:
        """How many events were dropped because this subscriber fell ``maxlen`` behind."""
        return self._dropped

    @property
    def closed(self) -> bool:
        return self._closed

    def get_nowait(self) -> list[RuntimeEvent]:
        """Every queued event, oldest first (an empty list when there are none)."""
        with self._cond:
            return self._drain()

    def wait(self, timeout: float | None = None) -> list[RuntimeEvent]:
        """Block until an event is queued (or ``timeout`` [s] wall time passes), then drain.

        Returns:
            The queued events, oldest first; empty on timeout or when unsubscribed.
        """
        with self._cond:
            self._cond.wait_for(lambda: bool(self._queue) or self._closed, timeout)
            return self._drain()

    async def get(self) -> list[RuntimeEvent]:
        """Await the next events (at least one), oldest first; empty once unsubscribed."""
        loop = asyncio.get_running_loop()
        while True:
            with self._cond:
                if self._queue or self._closed:
                    return self._drain()
                future: asyncio.Future[None] = loop.create_future()
                self._async_waiters.append((loop, future))
            await future

    def _put(self, event: RuntimeEvent) -> None:
        with self._cond:
            if self._closed:
                return
            if len(self._queue) >= self.maxlen:
                self._queue.popleft()
                self._dropped += 1
                if self._dropped == 1 or self._dropped % 1000 == 0:
                    log.warning("slow event subscriber: %d events dropped", self._dropped)
            self._queue.append(event)
            self._cond.notify_all()
            waiters, self._async_waiters = self._async_waiters, []
        _wake(waiters)

    def _close(self) -> None:
        with self._cond:
            self._closed = True
            self._cond.notify_all()
            waiters, self._async_waiters = self._async_waiters, []
        _wake(waiters)

    def _drain(self) -> list[RuntimeEvent]:
        events = list(self._queue)
        self._queue.clear()
        return events


def _wake(waiters: list[tuple[asyncio.AbstractEventLoop, asyncio.Future[None]]]) -> None:
    for loop, future in waiters:
        try:
            loop.call_soon_threadsafe(_resolve, future)
        except RuntimeError:
            # The subscriber's loop is closed: it is gone, and nobody waits any more.
            log.debug("event subscriber's loop is closed")


def _resolve(future: asyncio.Future[None]) -> None:
    if not future.done():
        future.set_result(None)


class EventBus:
    """Publishes runtime events to every subscription, never blocking the publisher."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._subscriptions: tuple[Subscription, ...] = ()

    def subscribe(self, maxlen: int = 1000) -> Subscription:
        """A new subscription receiving every event published from now on.

        Args:
            maxlen: events kept for this subscriber before the oldest are dropped.

        Raises:
            InvalidRequest: ``maxlen`` < 1.
        """
        sub = Subscription(maxlen)
        with self._lock:
            self._subscriptions = (*self._subscriptions, sub)
        return sub

    def unsubscribe(self, subscription: Subscription) -> None:
        """Stop delivering to ``subscription`` and wake its waiters (idempotent)."""
        with self._lock:
            self._subscriptions = tuple(s for s in self._subscriptions if s is not subscription)
        subscription._close()

    @property
    def subscriber_count(self) -> int:
        return len(self._subscriptions)

    def publish(self, event: RuntimeEvent) -> None:
        """Queue ``event`` for every subscriber; full queues drop their oldest event."""
        log.debug("event %s", event)
        for sub in self._subscriptions:  # an immutable tuple: no lock needed to iterate
            sub._put(event)
