"""A real Galileo server on 127.0.0.1 port 0 over a real runtime on the seeded demo site.

Determinism (as the Yunji suite): the runtime's loop thread is NOT started. The servers run on
their own event-loop thread; runtime commands from handlers run at once under the runtime's
lock, and the test advances simulated time itself (``runtime.advance``) between requests, so
every run sees the same simulated history whatever the machine's speed.
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable, Iterator
from typing import Any, TypeVar

import httpx
import pytest

from polynav.protocols.galileo import GalileoConfig, serve
from polynav.protocols.galileo.server import GalileoServer
from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds.world import World
from tests.helpers.loop_thread import LoopThread

T = TypeVar("T")
HTTP_TIMEOUT = 20.0


class Harness:
    """The runtime, the servers, and an HTTP client for ``/api/v1`` (token added when set)."""

    def __init__(self, runtime: RobotRuntime, server: GalileoServer, loop: LoopThread) -> None:
        self.runtime = runtime
        self.server = server
        self.loop = loop
        self.base = f"http://127.0.0.1:{server.port}"
        self.http = httpx.Client(base_url=self.base, timeout=HTTP_TIMEOUT)
        self.token: str | None = None

    def request(self, method: str, path: str, *, params: dict[str, Any] | None = None,
                json: Any = None, **kwargs: Any) -> httpx.Response:
        """``method`` on ``/api/v1`` + ``path`` (a path starting ``/token`` or ``http`` is used
        as is)."""
        url = path if path.startswith(("/api/", "/token")) else "/api/v1" + path
        query = dict(params or {})
        if self.token is not None and "token" not in query:
            query["token"] = self.token
        return self.http.request(method, url, params=query, json=json, **kwargs)

    def get(self, url: str, /, **params: Any) -> httpx.Response:
        return self.request("GET", url, params=params)

    def delete(self, url: str, /, **params: Any) -> httpx.Response:
        return self.request("DELETE", url, params=params)

    def post(self, path: str, body: Any = None, **kwargs: Any) -> httpx.Response:
        return self.request("POST", path, json=body, **kwargs)

    def put(self, path: str, body: Any = None, **kwargs: Any) -> httpx.Response:
        return self.request("PUT", path, json=body, **kwargs)

    def ok(self, method: str, path: str, **kwargs: Any) -> Any:
        """The JSON of a 200 reply (fails the test on another status)."""
        response = self.request(method, path, **kwargs)
        assert response.status_code == 200, (method, path, response.status_code, response.text)
        return response.json()

    def advance_until(self, done: Callable[[], bool], timeout: float, step: float = 0.1,
                      pause: float = 0.0) -> bool:
        """Advance simulated time until ``done()``, checked between ``step`` s steps (a check
        that makes HTTP requests would be slow at every physics step), with ``pause`` s of wall
        time between steps for what a socket carries meanwhile."""
        deadline = self.runtime.now() + timeout
        while not done():
            if self.runtime.now() >= deadline:
                return False
            self.runtime.advance(step)
            if pause:
                time.sleep(pause)
        return True


@pytest.fixture
def runtime(world: World, store: SiteStore) -> RobotRuntime:
    return RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False))


def galileo_config(**changes: Any) -> GalileoConfig:
    """A config for tests: ephemeral ports, no announcements unless asked."""
    options: dict[str, Any] = {"port": 0, "ws_port": 0, "announce": False}
    options.update(changes)
    return GalileoConfig(**options)


@contextlib.contextmanager
def serving(runtime: RobotRuntime, config: GalileoConfig | None = None) -> Iterator[Harness]:
    """The Galileo servers for ``runtime`` on their own loop thread; closed at the end."""
    loop = LoopThread()
    server = loop.run(serve(runtime, config or galileo_config()))
    runtime.advance(0.5)  # out of the start-up BUSY
    h = Harness(runtime, server, loop)
    try:
        yield h
    finally:
        h.http.close()
        loop.run(server.close())
        loop.close()


@pytest.fixture
def galileo(runtime: RobotRuntime) -> Iterator[Harness]:
    with serving(runtime) as h:
        yield h
