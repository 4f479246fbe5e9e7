"""A uvicorn server that stops as soon as it is told, for every HTTP server polynav runs.

uvicorn notices ``should_exit`` on a 0.1 s tick and then sleeps another 0.1 s in its shutdown,
whether or not any connection is open, so each stop costs 0.1-0.2 s of nothing. A site that
stops and starts dialects, and a test suite that starts thousands of servers, pay that every
time. Here setting ``should_exit`` wakes the main loop at once, and a server with no open
connection skips the wait meant for connections to finish; one with connections still gets
uvicorn's graceful shutdown unchanged.
"""

from __future__ import annotations

import asyncio
import contextlib
import socket
from collections.abc import Iterator

import uvicorn

_TICK = 0.1  # s: uvicorn's tick, kept for its once-a-second Date header


class PromptServer(uvicorn.Server):
    """``uvicorn.Server`` whose stop takes no fixed sleeps.

    ``signals=False`` leaves SIGINT and SIGTERM to the caller: a process serving several apps
    (a building's robots, a fleet manager beside its broker) stops them all from one handler.
    """

    def __init__(self, config: uvicorn.Config, *, signals: bool = True) -> None:
        self._signals = signals
        self._stop_now = False
        self._wake: asyncio.Event | None = None
        self._loop: asyncio.AbstractEventLoop | None = None
        super().__init__(config)

    @property
    def should_exit(self) -> bool:
        return self._stop_now

    @should_exit.setter
    def should_exit(self, value: bool) -> None:
        """Set from any thread or a signal handler; wakes the serving loop."""
        self._stop_now = value
        if value and self._loop is not None and self._wake is not None:
            with contextlib.suppress(RuntimeError):  # the loop has already closed
                self._loop.call_soon_threadsafe(self._wake.set)

    @contextlib.contextmanager
    def capture_signals(self) -> Iterator[None]:
        if self._signals:
            with super().capture_signals():
                yield
        else:
            yield

    async def main_loop(self) -> None:
        self._loop = asyncio.get_running_loop()
        self._wake = asyncio.Event()
        counter = 0
        should_exit = await self.on_tick(counter)
        while not should_exit:
            counter = (counter + 1) % 864000
            with contextlib.suppress(asyncio.TimeoutError):
                await asyncio.wait_for(self._wake.wait(), _TICK)
            should_exit = await self.on_tick(counter)

    async def shutdown(self, sockets: list[socket.socket] | None = None) -> None:
        if self.server_state.connections or self.server_state.tasks:
            await super().shutdown(sockets)
            return
        for server in self.servers:
            server.close()
        for sock in sockets or []:
            sock.close()
        if not self.force_exit:
            await self.lifespan.shutdown()
