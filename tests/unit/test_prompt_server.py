"""The prompt uvicorn server: a stop wakes it at once (not on uvicorn's tick), an idle server
skips the wait meant for open connections, and a server with a connection open still shuts down
gracefully through uvicorn's own path."""

from __future__ import annotations

import signal
import socket
import threading

import httpx
import pytest
import uvicorn
from starlette.applications import Starlette
from starlette.responses import PlainTextResponse
from starlette.routing import Route

from polynav import prompt_server
from polynav.listen import tcp_listener
from polynav.prompt_server import PromptServer

HANG_GUARD = 30.0  # s: only a hung server comes anywhere near this


def _app() -> Starlette:
    async def hello(_request: object) -> PlainTextResponse:
        return PlainTextResponse("hello")

    return Starlette(routes=[Route("/", hello)])


class _Served:
    """A PromptServer on a loopback socket in a thread (as the tests' API server runs)."""

    def __init__(self) -> None:
        self.sock = tcp_listener("127.0.0.1", 0)
        self.port = int(self.sock.getsockname()[1])
        self.url = f"http://127.0.0.1:{self.port}/"
        self.server = PromptServer(uvicorn.Config(_app(), log_level="warning", lifespan="off"))
        self.thread = threading.Thread(target=self.server.run,
                                       kwargs={"sockets": [self.sock]}, daemon=True)

    def __enter__(self) -> _Served:
        self.thread.start()
        while not self.server.started:
            assert self.thread.is_alive()
            self.thread.join(0.005)
        return self

    def stop(self) -> bool:
        """Whether the server thread ended after ``should_exit`` was set from this thread."""
        self.server.should_exit = True
        self.thread.join(HANG_GUARD)
        return not self.thread.is_alive()

    def __exit__(self, *_exc: object) -> None:
        self.server.should_exit = True
        self.thread.join(HANG_GUARD)
        self.sock.close()


@pytest.fixture
def no_tick(monkeypatch: pytest.MonkeyPatch) -> None:
    """uvicorn's tick an hour long: a server that stops must have been woken by the stop."""
    monkeypatch.setattr(prompt_server, "_TICK", 3600.0)


def test_a_stop_from_another_thread_wakes_the_server(no_tick: None) -> None:
    with _Served() as served:
        assert httpx.get(served.url).text == "hello"
        assert served.stop()


def test_an_idle_server_skips_the_wait_for_connections(no_tick: None,
                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    graceful: list[bool] = []

    async def uvicorn_shutdown(self: uvicorn.Server, sockets: object = None) -> None:
        graceful.append(True)

    monkeypatch.setattr(uvicorn.Server, "shutdown", uvicorn_shutdown)
    with _Served() as served:
        with httpx.Client() as client:
            assert client.get(served.url).text == "hello"
        # the client's connection closed: wait until the server has seen it go
        for _ in range(1000):
            if not served.server.server_state.connections:
                break
            served.thread.join(0.01)
        assert served.stop()
        assert graceful == []
        with pytest.raises(OSError):  # the listener is closed
            socket.create_connection(("127.0.0.1", served.port), timeout=5)


def test_an_open_connection_gets_uvicorns_graceful_shutdown(no_tick: None) -> None:
    with _Served() as served, httpx.Client() as client:
        assert client.get(served.url).text == "hello"  # kept alive
        assert served.server.server_state.connections
        assert served.stop()
        assert not served.server.server_state.connections


def test_should_exit_reads_back_and_starts_false() -> None:
    server = PromptServer(uvicorn.Config(_app()))
    assert server.should_exit is False
    server.should_exit = True  # no loop yet: nothing to wake, no error
    assert server.should_exit is True


@pytest.mark.parametrize("signals", [True, False])
def test_signals_false_leaves_sigterm_to_the_caller(signals: bool) -> None:
    # A building serves one app per robot in one process: its own handler stops them all.
    before = signal.getsignal(signal.SIGTERM)
    server = PromptServer(uvicorn.Config(_app()), signals=signals)
    with server.capture_signals():
        inside = signal.getsignal(signal.SIGTERM)
    assert (inside is not before) is signals
    assert signal.getsignal(signal.SIGTERM) is before
