"""The Galileo entry lists the suite covers, and the key naming each entry.

An entry's key is ``"<METHOD> <path>"``; the three method + path pairs galileo-http-a lists twice
(two forms of ``PUT``/``DELETE /system/tts/records``, two ``GET /system/onvif_cameras``) add
``" @<seed_lines>"`` to tell them apart. Test modules name what they cover in a module-level
``COVERED`` dict (key -> test function name); ``test_coverage`` collects them.
"""

from __future__ import annotations

import json
from collections import Counter
from pathlib import Path
from typing import Any

from tests.conftest import DATA

SPEC_FILES = {
    "galileo-http-a": DATA / "spec" / "galileo-http-a.endpoints.json",
    "galileo-http-b": DATA / "spec" / "galileo-http-b.endpoints.json",
    "galileo-tasks-bt-ws": DATA / "spec" / "galileo-tasks-bt-ws.endpoints.json",
    "galileo-wire-protocols": DATA / "spec" / "galileo-wire-protocols.endpoints.json",
}


def _load(path: Path) -> list[dict[str, Any]]:
    data = json.loads(path.read_text(encoding="utf-8"))
    assert isinstance(data, list)
    return data


def keyed(entries: list[dict[str, Any]]) -> dict[str, dict[str, Any]]:
    """key -> entry, with ``@seed_lines`` on method + path pairs listed more than once."""
    counts = Counter((e["method"], e["path"]) for e in entries)
    out: dict[str, dict[str, Any]] = {}
    for e in entries:
        key = f"{e['method']} {e['path']}"
        if counts[(e["method"], e["path"])] > 1:
            key += f" @{e['seed_lines']}"
        assert key not in out, key
        out[key] = e
    return out


HTTP_A = keyed(_load(SPEC_FILES["galileo-http-a"]))
HTTP_B = keyed(_load(SPEC_FILES["galileo-http-b"]))
WS = keyed([e for e in _load(SPEC_FILES["galileo-tasks-bt-ws"]) if e["group"] == "ws"])
#: The task, action and automation-task endpoints (the tasks issue's).
TASKS = keyed([e for e in _load(SPEC_FILES["galileo-tasks-bt-ws"]) if e["group"] != "ws"])


def wire_keyed(protocol: str) -> dict[str, dict[str, Any]]:
    """The galileo-wire-protocols entries of ``protocol`` (``galileo-serial``, ...), keyed
    ``"<protocol> <method> <path>"`` (``"galileo-modbus register 40008"``)."""
    out: dict[str, dict[str, Any]] = {}
    for e in _load(SPEC_FILES["galileo-wire-protocols"]):
        if e["protocol"] == protocol:
            key = f"{e['protocol']} {e['method']} {e['path']}"
            assert key not in out, key
            out[key] = e
    return out


SERIAL = wire_keyed("galileo-serial")
ROS = wire_keyed("galileo-ros")
MODBUS = wire_keyed("galileo-modbus")
UDP = wire_keyed("galileo-udp")
SDK = wire_keyed("galileo-sdk")
WIRE = {**SERIAL, **ROS, **MODBUS, **UDP, **SDK}
ALL = {**HTTP_A, **HTTP_B, **WS, **TASKS, **WIRE}
