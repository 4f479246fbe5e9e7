"""A real uvicorn server on 127.0.0.1 (an OS-chosen port) in a thread, for tests over HTTP."""

from __future__ import annotations

import threading
import time

import uvicorn
from fastapi import FastAPI

from polynav.listen import tcp_listener


class ServerThread:
    """Serve ``app`` until :meth:`stop`; ``url`` is ``http://127.0.0.1:<port>``."""

    def __init__(self, app: FastAPI) -> None:
        self._sock = tcp_listener("127.0.0.1", 0)  # as `polynav run` makes it
        self.port = self._sock.getsockname()[1]
        self.url = f"http://127.0.0.1:{self.port}"
        config = uvicorn.Config(
            app, log_level="warning", lifespan="off", ws="websockets-sansio"
        )
        self._server = uvicorn.Server(config)
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
