"""Coverage of the Galileo entry lists: every entry has a test, or is on the exact to-do list.

Each test module of this package names what it covers in a module-level ``COVERED`` dict: entry
key (:mod:`tests.protocols.galileo.spec`) -> the name of a test function in that module that
exercises it over real HTTP or WebSocket against a running polynav. The to-do lists below hold
the entries not built yet; an entry is in exactly one of the two places, so covering an entry
means moving it out of its to-do list in the same commit (the lists are strict both ways).

The blocks have owners (see the briefs): galileo-http-a apart from token and status is
"gsys"'s; galileo-http-b and the WebSocket entries are "galileo"'s; the task entries are the
tasks issue's (32).
"""

from __future__ import annotations

import tests.protocols.galileo as package
from polynav.protocols.galileo import routes
from tests.helpers.coverage import covered_entries
from tests.protocols.galileo import spec

# galileo-http-a entries without a test yet (owner: gsys): none left.
TODO_HTTP_A: set[str] = set()

# galileo-http-b entries without a test yet (owner: galileo): none left.
TODO_HTTP_B: set[str] = set()

# WebSocket entries without a test yet (owner: galileo): none left.
TODO_WS: set[str] = set()

# Task entries without a test yet (issue 32): none left.
TODO_TASKS: set[str] = set()

# galileo-wire-protocols entries without a test yet (issue 35), one set per owner: serial and
# ROS (the lead), Modbus (gw-modbus), UDP (gw-udp), SDK (the SDK client).
TODO_SERIAL: set[str] = set()
TODO_MODBUS: set[str] = set()
TODO_UDP: set[str] = set()
TODO_SDK: set[str] = set()

TODO = (TODO_HTTP_A | TODO_HTTP_B | TODO_WS | TODO_TASKS | TODO_SERIAL | TODO_MODBUS | TODO_UDP
        | TODO_SDK)


COVERED = covered_entries(package)


def test_every_entry_has_a_test_or_is_on_the_todo_list() -> None:
    missing = sorted(set(spec.ALL) - set(COVERED) - TODO)
    assert missing == [], "entries with neither a test nor a to-do line"


def test_the_todo_list_holds_no_covered_or_unknown_entry() -> None:
    assert sorted(TODO & set(COVERED)) == [], "covered entries still on the to-do list"
    assert sorted(TODO - set(spec.ALL)) == [], "to-do lines that are no entry"
    assert sorted(set(COVERED) - set(spec.ALL)) == [], "COVERED keys that are no entry"


def test_the_todo_blocks_hold_their_own_lists_entries() -> None:
    assert TODO_HTTP_A <= set(spec.HTTP_A)
    assert TODO_HTTP_B <= set(spec.HTTP_B)
    assert TODO_WS <= set(spec.WS)
    assert TODO_TASKS <= set(spec.TASKS)
    assert TODO_SERIAL <= set(spec.SERIAL) | set(spec.ROS)
    assert TODO_MODBUS <= set(spec.MODBUS)
    assert TODO_UDP <= set(spec.UDP)
    assert TODO_SDK <= set(spec.SDK)


def test_every_covered_http_entry_is_served() -> None:
    served = {f"{method} {path}" for method, path in routes.table()}
    http = {k for k in COVERED if k in spec.HTTP_A or k in spec.HTTP_B or k in spec.TASKS}
    unserved = sorted(k for k in http if k.split(" @")[0] not in served)
    assert unserved == []


#: Served beside the entries on purpose: /token without the prefix (A-02), and
#: multi_map_task by GET as well as POST (its method is not stated, A-12).
ALIASES = {"GET /token", "GET /api/v1/navigation/multi_map_task"}


def test_every_served_endpoint_is_an_entry() -> None:
    entries = {k.split(" @")[0] for k in spec.HTTP_A | spec.HTTP_B | spec.TASKS}
    extra = sorted(
        f"{method} {path}" for method, path in routes.table()
        # A ``{param}`` tail is the path form of an entry's parameter (galileo-http-a A-20).
        if f"{method} {path.split('{')[0]}" not in entries | ALIASES
    )
    assert extra == [], "served endpoints that are no entry of the lists"
