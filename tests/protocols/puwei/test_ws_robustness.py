"""The Puwei WebSocket keeps a session through frames and failures the spec does not foresee
(STYLE R4: a bad request never kills the connection): binary frames, and a runtime command
failing with an error that is no :class:`~polynav.errors.PolynavError`.

Each gets O_EVENT 1029 (EVENT_WARN_INVALID_CMD) to the sender alone, and the same session then
still carries a good command through to the robot.
"""

from __future__ import annotations

import pytest

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
