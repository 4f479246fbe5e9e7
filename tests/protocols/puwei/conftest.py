"""A real Puwei server on 127.0.0.1 port 0 over a real runtime on the seeded demo site.

Determinism (as the Galileo and Yunji suites): the runtime's loop thread is NOT started. The
servers run on their own event-loop thread; runtime commands from handlers run at once under
the runtime's lock, and the test advances simulated time itself (``runtime.advance``) between
requests, so every run sees the same simulated history whatever the machine's speed.
"""

from __future__ import annotations

import contextlib
import datetime as dt
from collections.abc import Callable, Iterator
from typing import Any, TypeVar

import httpx
import pytest

from polynav.protocols.puwei import PuweiConfig, serve
from polynav.protocols.puwei.server import PuweiServer
from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds.world import World
from tests.helpers.loop_thread import LoopThread

T = TypeVar("T")
HTTP_TIMEOUT = 20.0
#: The robot's calendar at clock 0 in these tests: Wednesday 2026-01-07, 09:00.
EPOCH = dt.datetime(2026, 1, 7, 9, 0, 0)
#: A map of the demo site and a point on it.
MAP = "floor1"


class Harness:
    """The runtime, the server, and an HTTP client that sends the token once logged in."""

    def __init__(self, runtime: RobotRuntime, server: PuweiServer, loop: LoopThread) -> None:
        self.runtime = runtime
        self.server = server
        self.loop = loop
        self.base = f"http://127.0.0.1:{server.port}"
        self.http = httpx.Client(base_url=self.base, timeout=HTTP_TIMEOUT)
        self.token: str | None = None

    def login(self) -> str:
        response = self.http.post("/api/user/login",
                                  json={"username": "admin", "password": "admin"})
        assert response.status_code == 200
        assert response.json()["code"] == 0, response.text
        self.token = response.headers["authorization"]
        return self.token

    def headers(self) -> dict[str, str]:
        return {} if self.token is None else {"authorization": self.token}

    def get(self, path: str, **params: Any) -> httpx.Response:
        return self.http.get(path, params=params, headers=self.headers())

    def post(self, path: str, body: Any = None, **kwargs: Any) -> httpx.Response:
        return self.http.post(path, json=body, headers=self.headers(), **kwargs)

    def call(self, path: str, **params: Any) -> Any:
        """GET ``path``; the envelope (HTTP 200 and a well-formed envelope asserted)."""
        return envelope(self.get(path, **params))

    def ok(self, path: str, **params: Any) -> Any:
        """GET ``path``; its ``data`` (code 0 asserted)."""
        body = self.call(path, **params)
        assert body["code"] == 0, (path, body)
        return body["data"]

    def advance_until(self, done: Callable[[], bool], timeout: float, step: float = 0.1
                      ) -> bool:
        """Advance simulated time until ``done()``, checked every ``step`` s."""
        deadline = self.runtime.now() + timeout
        while not done():
            if self.runtime.now() >= deadline:
                return False
            self.runtime.advance(step)
        return True

    def navigate(self, map_name: str = MAP) -> None:
        """Start navigation on ``map_name`` and wait until it runs."""
        self.ok(f"/api/roslaunch/navigation/{map_name}")
        assert self.advance_until(lambda: self.runtime.status().mode == "navigating", 10.0)


def envelope(response: httpx.Response) -> dict[str, Any]:
    """The reply's envelope; HTTP 200 and the three documented fields asserted."""
    assert response.status_code == 200, response.text
    body = response.json()
    assert set(body) == {"code", "data", "msg"}, body
    assert isinstance(body["code"], int) and isinstance(body["msg"], str)
    if body["code"] != 0:
        assert body["msg"], body
    return body


def refused(response: httpx.Response) -> dict[str, Any]:
    """The envelope of a refused request: non-zero code with a message."""
    body = envelope(response)
    assert body["code"] != 0 and body["msg"], body
    return body


def puwei_config(**changes: Any) -> PuweiConfig:
    """A config for tests: ephemeral ports, loopback only."""
    options: dict[str, Any] = {"port": 0, "discovery_port": None}
    options.update(changes)
    return PuweiConfig(**options)


@pytest.fixture
def runtime(world: World, store: SiteStore) -> RobotRuntime:
    return RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False,
                                                                     calendar_epoch=EPOCH))


@contextlib.contextmanager
def serving(runtime: RobotRuntime, config: PuweiConfig | None = None) -> Iterator[Harness]:
    """The Puwei servers for ``runtime`` on their own loop thread; closed at the end."""
    loop = LoopThread()
    server = loop.run(serve(runtime, config or puwei_config()))
    runtime.advance(0.5)  # out of the start-up BUSY
    h = Harness(runtime, server, loop)
    try:
        yield h
    finally:
        h.http.close()
        loop.run(server.close())
        loop.close()


@pytest.fixture
def puwei(runtime: RobotRuntime) -> Iterator[Harness]:
    """A served runtime, logged in."""
    with serving(runtime) as h:
        h.login()
        yield h
