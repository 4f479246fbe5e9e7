"""Coverage of ``yunji-api.endpoints.json``: every entry (reserved codes excepted) has a test.

Each test module of this package names what it covers in a module-level ``COVERED`` dict: entry
key (``"<method> <section> <path>"``) -> the name of a test function in that module that
exercises it over a real socket. This module collects them. Every command and every notification
code polynav produces must be covered; a code polynav has no feature for must be in
``events.NOT_PRODUCED`` with the reason (reserved codes are not entries to cover).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

import tests.protocols.yunji as package
from polynav.protocols.yunji import events as yunji_events
from tests.conftest import DATA
from tests.helpers.coverage import covered_entries

SPEC = DATA / "spec" / "yunji-api.endpoints.json"


def _entries(path: Path) -> list[dict[str, Any]]:
    data = json.loads(path.read_text(encoding="utf-8"))
    assert isinstance(data, list)
    return data


def _key(entry: dict[str, Any]) -> str:
    return f"{entry['method']} {entry['section']} {entry['path']}"


ENTRIES = _entries(SPEC)
LIVE = [e for e in ENTRIES if not e.get("reserved")]
COVERED = covered_entries(package, skip='test_endpoints')

NOT_PRODUCED = {f"notify 10 {code}" for code in yunji_events.NOT_PRODUCED}


def test_every_endpoint_entry_has_a_test() -> None:
    keys = [_key(e) for e in LIVE]
    assert len(keys) == len(set(keys)), "entry keys must be unique"
    assert sorted(set(keys) - set(COVERED) - NOT_PRODUCED) == [], "entries without a test"
    assert sorted((set(COVERED) | NOT_PRODUCED) - set(keys)) == [], "stale entries"
    assert NOT_PRODUCED.isdisjoint(COVERED), "a code is both produced and not produced"


def test_produced_codes_are_exactly_the_covered_notifications() -> None:
    covered = {key.split()[-1] for key in COVERED if key.startswith("notify ")}
    assert covered == set(yunji_events.PRODUCED)


@pytest.mark.parametrize("code", sorted(yunji_events.NOT_PRODUCED))
def test_a_code_polynav_cannot_produce_is_catalogued_with_the_reason(code: str) -> None:
    """Codes whose trigger polynav has no feature for (containers, cabins, ...) are in the
    catalogue with the spec's level and description, never emitted, and say why."""
    assert code in yunji_events.NOTIFICATIONS
    assert code not in yunji_events.PRODUCED
    assert len(yunji_events.NOT_PRODUCED[code]) > 10


def test_the_catalogue_holds_every_defined_code_verbatim() -> None:
    codes = {e["path"] for e in LIVE if e["method"] == "notify"}
    assert set(yunji_events.NOTIFICATIONS) == codes
    assert yunji_events.NOTIFICATIONS["01012"] == ("warning", "Failed to leave charging plie.")
    assert yunji_events.NOTIFICATIONS["04023"] == ("warning", "Take lift more than 3 minutes.")
    assert yunji_events.NOTIFICATIONS["04002"][0] == "info"  # sic (§A-N3)
