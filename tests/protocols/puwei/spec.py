"""The Puwei entry list the suite covers, and the key naming each entry.

An entry's key is ``"<METHOD> <path>"`` as ``puwei-api.endpoints.json`` writes them
(``"GET /api/map/list"``, ``"udp 224.0.0.1:9999 \\"discovery\\""``, ``"ws-in type=1/I_INIT"``).
Test modules name what they cover in a module-level ``COVERED`` dict (key -> test function
name); ``test_coverage`` collects them. ``EXTRA`` are the endpoints the issue adds beyond the
document (item 2), keyed the same way and covered the same way.
"""

from __future__ import annotations

import json
from typing import Any

from tests.conftest import DATA

SPEC_FILE = DATA / "spec" / "puwei-api.endpoints.json"


def _load() -> list[dict[str, Any]]:
    data = json.loads(SPEC_FILE.read_text(encoding="utf-8"))
    assert isinstance(data, list)
    return data


def key(entry: dict[str, Any]) -> str:
    return f"{entry['method']} {entry['path']}"


ENTRIES = _load()
ALL: dict[str, dict[str, Any]] = {key(e): e for e in ENTRIES}
assert len(ALL) == len(ENTRIES), "two entries share a key"
#: The HTTP endpoints of the document.
HTTP = {k: e for k, e in ALL.items() if e["protocol"] == "puwei-http"}
#: The WebSocket connection and message entries (the WebSocket side's).
WS = {k: e for k, e in ALL.items() if e["protocol"] == "puwei-ws"}
UDP = {k: e for k, e in ALL.items() if e["protocol"] == "puwei-udp"}

#: Issue 33 item 2: endpoints real Puwei clients call that the document lacks.
EXTRA = {
    "GET /api/robot/status",
    "GET /api/robot/clear",
    "GET /api/robot/pause",
    "GET /api/robot/charge",
    "POST /api/map/upload",
    "GET /api/task/run/:name",
    "GET /api/scheduler/release",
}
