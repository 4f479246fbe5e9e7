from __future__ import annotations

import pytest

from polynav.api import ApiConfig
from polynav.api.errors import status_and_code
from polynav.api.routes.ws import StatusPacer
from polynav.errors import ConfigError, Conflict, InvalidRequest, NotFound, StorageError
from polynav.planning.errors import NoPath
from polynav.worlds.errors import WorldFormatError


@pytest.mark.parametrize(("changes", "key"), [
    ({"port": 70000}, "api.port"), ({"port": -1}, "api.port"), ({"host": ""}, "api.host"),
    ({"ws_default_rate": 0.0}, "api.ws_default_rate"),
    ({"ws_default_rate": 60.0}, "api.ws_default_rate"),
    ({"ws_max_rate": 0.0}, "api.ws_max_rate"), ({"ws_poll_interval": 0.0}, "api.ws_poll_interval"),
])
def test_api_config_range_checks_name_the_key(changes: dict[str, object], key: str) -> None:
    with pytest.raises(ConfigError) as error:
        ApiConfig(**changes)  # type: ignore[arg-type]
    assert error.value.key == key


def test_errors_map_along_the_mro() -> None:
    assert status_and_code(NotFound("point", "x")) == (404, "not_found")
    assert status_and_code(Conflict("busy")) == (409, "conflict")
    # The schemas refuse malformed requests (422) before any polynav code runs; an
    # InvalidRequest from the runtime or the store refuses a well-formed one.
    assert status_and_code(InvalidRequest("x", "bad")) == (409, "invalid_request")
    assert status_and_code(WorldFormatError("x", "bad")) == (409, "invalid_request")
    assert status_and_code(StorageError("disk")) == (500, "storage_error")
    assert status_and_code(NoPath("blocked")) == (400, "bad_request")
    assert status_and_code(RuntimeError("bug")) == (500, "internal")


def test_status_pacer_keeps_the_rate_on_sim_time_and_skips_after_a_stall() -> None:
    pacer = StatusPacer(5.0)
    sent = [t / 10 for t in range(0, 21) if pacer.due(t / 10)]
    assert sent == [0.0, 0.2, 0.4, 0.6, 0.8, 1.0, 1.2, 1.4, 1.6, 1.8, 2.0]
    assert pacer.due(5.0)  # after a stall: one message, no burst
    assert not pacer.due(5.1)
    assert pacer.due(5.2)


def test_status_pacer_never_sends_within_half_a_period_after_a_late_message() -> None:
    pacer = StatusPacer(5.0)
    assert pacer.due(0.0) and pacer.due(0.2) and pacer.due(0.4)
    assert pacer.due(0.76)  # 0.16 s late (a busy machine): not due again at 0.8
    assert not pacer.due(0.8) and not pacer.due(0.9)
    assert pacer.due(0.96)
    assert pacer.due(1.22)  # 0.06 s late: the schedule holds
    assert not pacer.due(1.3) and pacer.due(1.36)
