"""A connection's outgoing frames, in the order the vendors' contracts promise, and bounded.

Every dialect server that pushes events on the same connection as it answers commands keeps one
:class:`Outbox` per connection, and so gets the same two guarantees:

* **A command's reply comes before the events it causes.** A real robot answers a command, then
  notifies; client code that sends a command and reads one line expects the reply. The runtime
  may publish an event (move started, e-stop on) while the handler is still running, and the
  event pump can deliver it before the handler returns. So while a command of this connection
  is in flight (:meth:`Outbox.begin_command` ... :meth:`Outbox.reply`), events and status frames
  for the connection are held, and they follow the reply. Other connections are not held.
* **A reader that lags costs a bounded amount.** Status frames (periodic callbacks) are
  coalesced to the newest per topic while unsent; events and replies are never dropped: when
  more than ``limit`` of them wait, the connection is closed with a reason
  (:attr:`Outbox.closed_reason`) instead of growing without bound or losing one silently.

The outbox is transport-agnostic (bytes or any frame object) and lives on one asyncio loop;
the server's writer task awaits :meth:`Outbox.get` and writes what it returns.
"""

from __future__ import annotations

import asyncio
import logging
from collections import deque
from dataclasses import dataclass
from typing import Generic, TypeVar

log = logging.getLogger(__name__)

Frame = TypeVar("Frame")


class OutboxClosed(Exception):
    """Raised by :meth:`Outbox.get` once the outbox is closed and empty."""


@dataclass(slots=True)
class _Entry(Generic[Frame]):
    frame: Frame
    status_key: str | None = None  # set for a coalescable status frame


class Outbox(Generic[Frame]):
    """One connection's queue of outgoing frames.

    Args:
        limit: replies and events that may wait unsent before the connection is closed as not
            reading. Coalesced status frames do not count (there is at most one per topic).
    """

    def __init__(self, limit: int) -> None:
        if limit < 1:
            raise ValueError(f"limit must be >= 1, got {limit}")
        self.limit = limit
        self._queue: deque[_Entry[Frame]] = deque()
        self._held: deque[_Entry[Frame]] = deque()
        self._status: dict[str, _Entry[Frame]] = {}  # unsent status frames by key
        self._commands = 0
        self._counted = 0  # replies and events in _queue and _held
        self._ready = asyncio.Event()
        self.closed_reason: str | None = None
        self.coalesced = 0

    @property
    def closed(self) -> bool:
        return self.closed_reason is not None

    @property
    def pending(self) -> int:
        """Frames waiting to be written (held ones included)."""
        return len(self._queue) + len(self._held)

    def begin_command(self) -> None:
        """A command of this connection is being answered: hold what is not its reply."""
        self._commands += 1

    def reply(self, frame: Frame) -> None:
        """Queue the reply of the oldest command in flight; then release what was held."""
        self._commands = max(0, self._commands - 1)
        self._push(_Entry(frame), counted=True)
        if self._commands == 0 and self._held:
            self._queue.extend(self._held)
            self._held.clear()
            self._ready.set()

    def event(self, frame: Frame) -> None:
        """Queue an event (a notification): never dropped, never ahead of a pending reply."""
        entry: _Entry[Frame] = _Entry(frame)
        if self._commands:
            self._hold(entry, counted=True)
        else:
            self._push(entry, counted=True)

    def status(self, frame: Frame, key: str) -> None:
        """Queue a periodic status frame; an unsent one with the same ``key`` is replaced."""
        if self.closed:
            return
        waiting = self._status.get(key)
        if waiting is not None:
            waiting.frame = frame
            self.coalesced += 1
            return
        entry: _Entry[Frame] = _Entry(frame, status_key=key)
        self._status[key] = entry
        if self._commands:
            self._held.append(entry)
        else:
            self._queue.append(entry)
            self._ready.set()

    def close(self, reason: str) -> None:
        """Close: :meth:`get` returns what is queued, then raises :class:`OutboxClosed`."""
        if self.closed_reason is None:
            self.closed_reason = reason
            self._held.clear()
            self._ready.set()

    async def get(self) -> Frame:
        """The next frame to write, waiting for one.

        Raises:
            OutboxClosed: the outbox was closed and everything queued before was taken.
        """
        while not self._queue:
            if self.closed:
                raise OutboxClosed(self.closed_reason)
            self._ready.clear()
            await self._ready.wait()
        return self._pop()

    def get_nowait(self) -> Frame | None:
        """The next frame to write if one is ready, else ``None``: a server whose transport is
        not backed up writes at once instead of waking its writer task (one task switch per
        reply saved; the order is the same, since only the caller and the writer take)."""
        return self._pop() if self._queue else None

    def _pop(self) -> Frame:
        entry = self._queue.popleft()
        if entry.status_key is not None:
            del self._status[entry.status_key]
        else:
            self._counted -= 1
        return entry.frame

    def _push(self, entry: _Entry[Frame], *, counted: bool) -> None:
        if self.closed or not self._admit(counted):
            return
        self._queue.append(entry)
        self._ready.set()

    def _hold(self, entry: _Entry[Frame], *, counted: bool) -> None:
        if self.closed or not self._admit(counted):
            return
        self._held.append(entry)

    def _admit(self, counted: bool) -> bool:
        if not counted:
            return True
        if self._counted >= self.limit:
            reason = f"not reading: {self._counted} replies and events unsent"
            log.warning("outbox: %s; closing the connection", reason)
            self.close(reason)
            return False
        self._counted += 1
        return True
