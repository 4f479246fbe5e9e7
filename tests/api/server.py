"""A real uvicorn server on 127.0.0.1 (an OS-chosen port) in a thread, for tests over HTTP."""

from __future__ import annotations

import contextlib
import threading
import time
from collections.abc import Iterator
from typing import Any

import httpx
import uvicorn
from fastapi import FastAPI

from polynav.api import ApiConfig, create_app
from polynav.listen import tcp_listener
from polynav.prompt_server import PromptServer


class ServerThread:
    """Serve ``app`` until :meth:`stop`; ``url`` is ``http://127.0.0.1:<port>``."""

    def __init__(self, app: FastAPI) -> None:
        self._sock = tcp_listener("127.0.0.1", 0)  # as `polynav run` makes it
        self.port = self._sock.getsockname()[1]
        self.url = f"http://127.0.0.1:{self.port}"
        config = uvicorn.Config(
            app, log_level="warning", lifespan="off", ws="websockets-sansio"
        )
        self._server = PromptServer(config)
        self._thread = threading.Thread(
            target=self._server.run, kwargs={"sockets": [self._sock]}, daemon=True
        )

    def start(self) -> ServerThread:
        self._thread.start()
        deadline = time.monotonic() + 30.0
        while not self._server.started:  # uvicorn has no start callback: wait for its flag
            if not self._thread.is_alive() or time.monotonic() > deadline:
                raise RuntimeError("the test server did not start")
            time.sleep(0.005)
        return self

    def stop(self) -> None:
        self._server.should_exit = True
        self._thread.join(timeout=30.0)
        self._sock.close()


@contextlib.contextmanager
def native_client(
    runtime: Any, *, timeout: float = 10.0, auth: bool | None = None
) -> Iterator[httpx.Client]:
    """An HTTP client of the native API served around ``runtime`` (a real one or a fake) on
    an ephemeral port, for as long as the block runs (``auth=True``: asking for a login)."""
    server = ServerThread(create_app(runtime, ApiConfig(port=0, auth=auth))).start()
    try:
        with httpx.Client(base_url=server.url, timeout=timeout) as client:
            yield client
    finally:
        server.stop()
