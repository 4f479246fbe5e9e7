"""Coverage of ``yunji-api.endpoints.json``: every entry (reserved codes excepted) has a test.

Each test module of this package names what it covers in a module-level ``COVERED`` dict: entry
key (``"<method> <section> <path>"``) -> the name of a test function in that module. This module
collects them. An entry nobody covers yet is pending: commands in ``PENDING_COMMANDS`` get a
strict xfail that asks for what the spec promises (an ``OK`` reply on the demo site) and
genuinely fails today; pending notification codes get a strict xfail asking for the code in the
catalogue of produced codes. When an entry gets covered its xfail disappears on its own; an entry
neither covered nor pending fails the coverage test.
"""

from __future__ import annotations

import importlib
import json
import pkgutil
from pathlib import Path
from typing import Any

import pytest

import tests.protocols.yunji as package
from polynav.protocols.yunji import events as yunji_events
from tests.conftest import SHARED
from tests.protocols.yunji.conftest import Client

SPEC = SHARED / "spec" / "yunji-api.endpoints.json"


def _entries(path: Path) -> list[dict[str, Any]]:
    if not path.is_file():
        return []
    data = json.loads(path.read_text(encoding="utf-8"))
    assert isinstance(data, list)
    return data


def _key(entry: dict[str, Any]) -> str:
    return f"{entry['method']} {entry['section']} {entry['path']}"


def _covered() -> dict[str, tuple[str, str]]:
    """entry key -> (test module, test name), from every test module's ``COVERED``."""
    out: dict[str, tuple[str, str]] = {}
    for info in pkgutil.iter_modules(package.__path__):
        if not info.name.startswith("test_") or info.name == "test_endpoints":
            continue
        module = importlib.import_module(f"{package.__name__}.{info.name}")
        for key, test_name in getattr(module, "COVERED", {}).items():
            assert key not in out, f"{key} is covered twice: {out[key]} and {info.name}"
            assert callable(getattr(module, test_name, None)), f"{key}: no {info.name}.{test_name}"
            out[key] = (info.name, test_name)
    return out


ENTRIES = _entries(SPEC)
LIVE = [e for e in ENTRIES if not e.get("reserved")]
COVERED = _covered()

# Not implemented yet: entry -> a request the spec says is answered OK on the demo site.
PENDING_COMMANDS: dict[str, str] = {
    "cmd 1.2 /api/move": "/api/move?markers=lobby,front_desk&count=1",
    "cmd 9.2 /api/request_data?topic=human_detection":
        "/api/request_data?topic=human_detection&frequency=0.5",
    "cmd 13.1 /api/wifi/list": "/api/wifi/list",
    "cmd 13.2 /api/wifi/connect": "/api/wifi/connect?SSID=polynav&password=secret",
    "cmd 13.3 /api/wifi/get_active_connection": "/api/wifi/get_active_connection",
    "cmd 13.4 /api/wifi/info": "/api/wifi/info",
    "cmd 13.5 /api/wifi/detail_list": "/api/wifi/detail_list",
    "cmd 14.5 /api/map/accessible_point_query": "/api/map/accessible_point_query?x=8.0&y=8.5",
    "cmd 14.6 /api/map/distance_probe": "/api/map/distance_probe?x=8.0&y=8.5",
    "cmd 15 /api/shutdown": "/api/shutdown?reboot=true",
    "cmd 16.2 /api/software/check_for_update": "/api/software/check_for_update",
    "cmd 16.3 /api/software/update": "/api/software/update",
    "cmd 16.4 /api/software/restart": "/api/software/restart",
    "cmd 17.1 /api/LED/set_luminance": "/api/LED/set_luminance?value=50",
    "cmd 17.2 /api/LED/set_color": "/api/LED/set_color?r=255&g=0&b=0",
    "cmd 18 /api/diagnosis/get_result": "/api/diagnosis/get_result",
    "cmd 19 /api/get_power_status": "/api/get_power_status",
    "cmd 20 /api/get_planned_path": "/api/get_planned_path",
    "cmd 21 /api/lift_status": "/api/lift_status",
    "cmd 22 /api/make_plan":
        "/api/make_plan?start_x=8.0&start_y=8.5&start_floor=1&goal_x=5.5&goal_y=12.5&goal_floor=1",
}

PENDING_COMMANDS = {k: v for k, v in PENDING_COMMANDS.items() if k not in COVERED}
NOT_PRODUCED = {f"notify 10 {code}" for code in yunji_events.NOT_PRODUCED}
PENDING_NOTIFICATIONS = [
    _key(e)
    for e in LIVE
    if e["method"] == "notify" and _key(e) not in COVERED and _key(e) not in NOT_PRODUCED
]

_pending = pytest.mark.xfail(strict=True, reason="not implemented yet")


@pytest.mark.skipif(not ENTRIES, reason="shared/spec is not beside the checkout")
def test_every_endpoint_entry_has_a_test_or_a_pending_xfail() -> None:
    keys = [_key(e) for e in LIVE]
    assert len(keys) == len(set(keys)), "entry keys must be unique"
    accounted = set(COVERED) | set(PENDING_COMMANDS) | set(PENDING_NOTIFICATIONS) | NOT_PRODUCED
    assert sorted(set(keys) - accounted) == []
    assert sorted(accounted - set(keys)) == []  # nothing stale
    assert NOT_PRODUCED.isdisjoint(COVERED), "a produced code is listed as not produced"


@pytest.mark.parametrize("code", sorted(yunji_events.NOT_PRODUCED))
def test_a_code_polynav_cannot_produce_is_catalogued_with_the_reason(code: str) -> None:
    """Codes whose trigger polynav has no feature for (containers, cabins, ...) are in the
    catalogue with the spec's level and description, never emitted, and say why."""
    assert code in yunji_events.NOTIFICATIONS
    assert code not in yunji_events.PRODUCED
    assert len(yunji_events.NOT_PRODUCED[code]) > 10


@_pending
@pytest.mark.parametrize("key", sorted(PENDING_COMMANDS))
def test_pending_command_is_answered_ok(key: str, client: Client) -> None:
    command = PENDING_COMMANDS[key]
    reply = client.request(command)
    assert (reply["command"], reply["status"]) == (command.split("?")[0], "OK"), reply


@_pending
@pytest.mark.parametrize("key", PENDING_NOTIFICATIONS)
def test_pending_notification_is_produced(key: str) -> None:
    assert key.split()[-1] in yunji_events.PRODUCED
