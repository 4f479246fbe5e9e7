"""The transport around the handlers: unknown endpoints and methods answer the envelope, and the
WebSocket path is routed to the WebSocket side (``ws.py``), closed 1011 when that side is
missing."""

from __future__ import annotations

import sys

import pytest
from websockets.exceptions import ConnectionClosedError
from websockets.sync.client import connect

from tests.protocols.puwei.conftest import Harness, refused


def test_unknown_endpoint_and_wrong_method_answer_the_envelope(puwei: Harness) -> None:
    assert refused(puwei.get("/api/nothing/here"))["code"] == 3
    assert refused(puwei.post("/api/roslaunch/status", {}))["code"] == 2
    assert refused(puwei.http.get("/api/user/login"))["code"] == 2


def test_websocket_is_closed_1011_when_the_websocket_side_is_missing(
        puwei: Harness, monkeypatch: pytest.MonkeyPatch) -> None:
    # None in sys.modules makes the import fail, whether ws.py exists yet or not.
    monkeypatch.setitem(sys.modules, "polynav.protocols.puwei.ws", None)
    url = f"ws://127.0.0.1:{puwei.server.port}/api/ws?token={puwei.token}"
    with connect(url, open_timeout=10) as ws, pytest.raises(ConnectionClosedError) as closed:
        ws.recv(timeout=10)
    assert closed.value.rcvd is not None and closed.value.rcvd.code == 1011


def test_websocket_is_handed_the_socket_and_the_shared_context(
        puwei: Harness, monkeypatch: pytest.MonkeyPatch) -> None:
    import types

    seen = []

    async def websocket_session(websocket, ctx):  # type: ignore[no-untyped-def]
        await websocket.accept()
        seen.append((websocket.query_params.get("token"), ctx.tokens.valid(puwei.token)))
        await websocket.send_text("hello")
        await websocket.close()

    fake = types.ModuleType("polynav.protocols.puwei.ws")
    fake.websocket_session = websocket_session  # type: ignore[attr-defined]
    monkeypatch.setitem(sys.modules, "polynav.protocols.puwei.ws", fake)
    url = f"ws://127.0.0.1:{puwei.server.port}/api/ws?token={puwei.token}"
    with connect(url, open_timeout=10) as ws:
        assert ws.recv(timeout=10) == "hello"
    assert seen == [(puwei.token, True)]
