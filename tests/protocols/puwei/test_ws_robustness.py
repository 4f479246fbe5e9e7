"""The Puwei WebSocket keeps a session through frames and failures the spec does not foresee
(STYLE R4: a bad request never kills the connection): binary frames, a runtime command
failing with an error that is no :class:`~polynav.errors.PolynavError`, and a client that stops
reading (closed 1008 with the reason, never fed without bound).

Each gets O_EVENT 1029 (EVENT_WARN_INVALID_CMD) to the sender alone, and the same session then
still carries a good command through to the robot.
"""

from __future__ import annotations

import asyncio
from typing import Any, cast

import pytest
from starlette.websockets import WebSocket

from polynav.protocols.puwei import messages as m
from polynav.protocols.puwei import ws
from polynav.protocols.puwei.context import Context
from polynav.runtime.robot_runtime import RobotRuntime
from tests.protocols.puwei.conftest import Harness
from tests.protocols.puwei.test_ws import client, wait_wall


@pytest.mark.parametrize("frame", [b"\x00\xff not text", b'{"type": 7, "data": true}'])
def test_a_binary_frame_gets_event_1029_and_the_session_goes_on(puwei: Harness,
                                                              frame: bytes) -> None:
    with client(puwei) as c:
        c.socket.send(frame)
        assert wait_wall(lambda: 1029 in c.events())
        assert c.of(1028)[-1]["msg"].startswith("输入的命令无效")
        assert not puwei.runtime.peripherals.buzzer_on  # a binary frame is never obeyed
        c.send(7, True)
        assert wait_wall(lambda: puwei.runtime.peripherals.buzzer_on)
        assert not c.closed.is_set()


def test_an_unexpected_failure_of_a_command_gets_event_1029_and_the_session_goes_on(
        puwei: Harness, monkeypatch: pytest.MonkeyPatch) -> None:
    peripherals = puwei.runtime.peripherals
    real = peripherals.set_buzzer

    def broken(on: bool) -> None:
        raise RuntimeError("buzzer driver fell over")

    with client(puwei) as c:
        monkeypatch.setattr(peripherals, "set_buzzer", broken)
        c.send(7, True)
        assert wait_wall(lambda: 1029 in c.events())
        monkeypatch.setattr(peripherals, "set_buzzer", real)
        c.send(7, True)
        assert wait_wall(lambda: peripherals.buzzer_on)
        assert not c.closed.is_set()


class _Tokens:
    """The one token this test hands out."""

    def valid(self, token: str | None) -> bool:
        return token == "t"


class _StuckSocket:
    """A client that never reads (its frames never leave) and never sends."""

    def __init__(self) -> None:
        self.query_params = {"token": "t"}
        self.sent = 0
        self.closed_with: tuple[int, str] | None = None

    async def accept(self) -> None:
        return None

    async def send_text(self, text: str) -> None:
        self.sent += 1
        await asyncio.Event().wait()

    async def receive(self) -> dict[str, Any]:
        await asyncio.Event().wait()
        raise AssertionError("unreachable")

    async def close(self, code: int = 1000, reason: str | None = None) -> None:
        self.closed_with = (code, reason or "")


def test_a_client_that_does_not_read_is_closed_1008_not_fed_for_ever(
        runtime: RobotRuntime) -> None:
    ctx = Context(runtime=runtime, tokens=_Tokens())
    socket_ = _StuckSocket()

    async def scenario() -> None:
        session = asyncio.create_task(ws.websocket_session(cast(WebSocket, socket_), ctx))
        while not ws.hub(ctx).sessions:
            await asyncio.sleep(0.01)
        for _ in range(ws.OUTBOX + 1):
            ws.hub(ctx).broadcast(m.event(m.REACHED))
        await asyncio.wait_for(session, 10)

    asyncio.run(scenario())
    assert socket_.closed_with is not None
    code, reason = socket_.closed_with
    assert code == 1008 and reason.startswith("not reading")
    assert socket_.sent == 1  # the stuck first frame; nothing piled up behind it was lost quietly
    assert not ws.hub(ctx).sessions
