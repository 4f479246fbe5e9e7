"""A dialect's asyncio servers on an event loop of their own, in a daemon thread.

``polynav run`` serves the native API with uvicorn on the main thread; every vendor dialect
runs beside it on its own loop, so a slow client of one never delays another's.
"""

from __future__ import annotations

import asyncio
import threading
from collections.abc import Callable, Coroutine
from typing import Any, Generic, Protocol, TypeVar


class Closable(Protocol):
    async def close(self) -> None: ...


class Startable(Closable, Protocol):
    async def start(self) -> None: ...


S = TypeVar("S", bound=Closable)
T = TypeVar("T", bound=Startable)


async def started(server: T) -> T:
    """``server`` started, or closed again (nothing left listening) and the error raised."""
    try:
        await server.start()
    except BaseException:
        await server.close()
        raise
    return server


class ServerThread(Generic[S]):
    """Start ``start()``'s server on a new loop in a thread named ``name``; :meth:`stop` closes
    the server and its clients, then ends the thread.

    Raises:
        whatever starting the server raised (a port taken), after the thread is ended.
    """

    def __init__(self, name: str, start: Callable[[], Coroutine[Any, Any, S]]) -> None:
        self._loop = asyncio.new_event_loop()
        self._thread = threading.Thread(target=self._loop.run_forever, name=name, daemon=True)
        self._thread.start()
        try:
            self.server: S = asyncio.run_coroutine_threadsafe(start(), self._loop).result()
        except BaseException:
            self._shutdown()
            raise

    @property
    def loop(self) -> asyncio.AbstractEventLoop:
        """The servers' event loop (to hand them work from other threads)."""
        return self._loop

    def stop(self) -> None:
        """Close the server and its clients, then end the thread."""
        asyncio.run_coroutine_threadsafe(self.server.close(), self._loop).result()
        self._shutdown()

    def _shutdown(self) -> None:
        asyncio.run_coroutine_threadsafe(self._loop.shutdown_default_executor(),
                                         self._loop).result()
        self._loop.call_soon_threadsafe(self._loop.stop)
        self._thread.join()
        self._loop.close()
