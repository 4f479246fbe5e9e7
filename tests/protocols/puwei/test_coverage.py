"""Coverage of the Puwei entry list: every entry has a test, or is on the exact to-do list.

Each test module of this package names what it covers in a module-level ``COVERED`` dict: entry
key (:mod:`tests.protocols.puwei.spec`) -> the name of a test function in that module that
exercises it over real HTTP, UDP or WebSocket against a running polynav. An entry is in exactly
one of the two places, so covering an entry means moving it out of its to-do list in the same
commit (the lists are strict both ways). The WebSocket entries are the WebSocket side's
(``ws.py``, issue 33 item 3), covered by its ``test_ws_*`` modules.
"""

from __future__ import annotations

import tests.protocols.puwei as package
from polynav.protocols.puwei import routes
from tests.helpers.coverage import covered_entries
from tests.protocols.puwei import spec

# The WebSocket connection and every message type (owner: the WebSocket side, ws.py). Its
# test_ws_* modules cover them; each covered key leaves this set in the same commit.
TODO_WS: set[str] = set()

TODO = set(TODO_WS)


COVERED = covered_entries(package)


def test_every_entry_has_a_test_or_is_on_the_todo_list() -> None:
    missing = sorted(set(spec.ALL) - set(COVERED) - TODO)
    assert missing == [], "entries with neither a test nor a to-do line"


def test_the_todo_list_holds_no_covered_or_unknown_entry() -> None:
    assert sorted(TODO & set(COVERED)) == [], "covered entries still on the to-do list"
    assert sorted(TODO - set(spec.ALL)) == [], "to-do lines that are no entry"
    known = set(spec.ALL) | spec.EXTRA
    assert sorted(set(COVERED) - known) == [], "COVERED keys that are no entry"


def test_every_extra_endpoint_of_the_issue_has_a_test() -> None:
    assert sorted(spec.EXTRA - set(COVERED)) == []


def test_every_served_http_endpoint_is_an_entry_with_a_test() -> None:
    served = {f"{e.method} {e.path}" for e in routes.table()}
    http = set(spec.HTTP) | spec.EXTRA
    assert sorted(served - http) == [], "served endpoints that are no entry"
    assert sorted(http - served) == [], "entries not served"
    assert sorted(served - set(COVERED)) == [], "served endpoints without a test"
