"""An ASGI app served by uvicorn on the running event loop, bound to a socket of our own so a
port that cannot be bound is an ``OSError`` at start, never a server exiting later. Transport
shared by the dialects that serve HTTP (each names itself in the error)."""

from __future__ import annotations

import asyncio
import contextlib
import socket

import uvicorn
from starlette.applications import Starlette

from polynav.listen import tcp_listener
from polynav.prompt_server import PromptServer


class HttpListener:
    """``app`` on ``host:port``; ``name`` says whose server in errors; ``ws`` is uvicorn's
    WebSocket implementation (its default when ``None``)."""

    def __init__(self, app: Starlette, host: str, port: int, *, name: str,
                 ws: str | None = None) -> None:
        options = {} if ws is None else {"ws": ws}
        config = uvicorn.Config(app, host=host, port=port, log_level="warning", lifespan="off",
                                access_log=False, **options)  # type: ignore[arg-type]
        self._server = PromptServer(config)
        self._name = name
        self._task: asyncio.Task[None] | None = None
        self._sock: socket.socket | None = None

    @property
    def port(self) -> int:
        assert self._sock is not None
        return int(self._sock.getsockname()[1])

    async def start(self) -> None:
        """Bind and serve.

        Raises:
            OSError: the port cannot be bound.
        """
        config = self._server.config
        self._sock = tcp_listener(config.host, config.port)
        self._task = asyncio.ensure_future(self._server.serve(sockets=[self._sock]))
        while not self._server.started:
            if self._task.done():
                with contextlib.suppress(SystemExit):
                    self._task.result()
                raise OSError(f"cannot serve on {config.host}:{config.port} ({self._name})")
            await asyncio.sleep(0.005)

    async def close(self) -> None:
        if self._task is not None:
            self._server.should_exit = True
            with contextlib.suppress(asyncio.CancelledError, SystemExit):
                await self._task
            self._task = None
        if self._sock is not None:
            self._sock.close()
            self._sock = None
