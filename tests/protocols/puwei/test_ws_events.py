"""Runtime events the Puwei WebSocket forwards beyond a client's own commands (puwei-api §9.5,
O_EVENT): the program-exit notices (2048, A23), each reaching every connected client.
"""

from __future__ import annotations

import pytest

from polynav.runtime import events
from tests.protocols.puwei.conftest import Harness
from tests.protocols.puwei.test_ws import client, wait_wall


@pytest.mark.parametrize(("notice", "detail"), [
    (events.SoftwareShutdownNotice(0.0), "shutdown"),
    (events.PowerOffNotice(0.0, reboot=True, after=5.0, delay=2.0), "reboot in 5 s"),
])
def test_a_shutdown_or_power_off_notice_is_event_2048_to_every_client(
        puwei: Harness, notice: events.RuntimeEvent, detail: str) -> None:
    with client(puwei) as c, client(puwei) as other:
        assert wait_wall(lambda: bool(c.of(1026) and other.of(1026)))
        puwei.runtime.publish(notice)
        for each in (c, other):
            assert wait_wall(lambda each=each: 2048 in each.events())
            exit_ = [e for e in each.of(1028) if e["code"] == 2048][0]
            assert exit_["msg"] == f"程序退出: {detail}"
