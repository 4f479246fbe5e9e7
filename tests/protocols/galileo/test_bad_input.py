"""Every endpoint, sent nothing, junk values or a broken body, answers a clear error in the
documented shape (never a 500, never a hang), and the robot stays as it was."""

from __future__ import annotations

from polynav.protocols.galileo import routes
from tests.protocols.galileo.conftest import Harness

JUNK = {"map": "\u0000nowhere", "map_name": "nowhere", "path": "x" * 300, "path_name": "",
        "index": "one", "id": "no-such-id", "name": "", "x": "nan", "y": "inf", "theta": "[]",
        "enabled": "maybe", "wait_time": "-1", "distance": "1e999", "angle": "x",
        "method": "9", "start_index": "-7", "level": "1.5", "server_id": "", "type": "boat",
        "swath_angle": "999", "map_id": ""}

#: 403 is the ``/fs`` refusal of a path outside the open folders (the junk ``path`` is relative).
SAFE_STATES = {200, 400, 403, 404, 405, 409}
#: Endpoints whose ``result`` is the answer (online or not), not whether a command was done.
RESULT_IS_THE_ANSWER = {"/api/v1/system/is_online"}
#: Endpoints with no parameters at all that change the mode: junk parameters do not stop them.
PARAMETERLESS = {"/api/v1/map/start", "/api/v1/navigation/start_schedule_mode"}


def _check(response_status: int, body: object, label: str) -> None:
    assert response_status in SAFE_STATES, label
    if response_status != 200:
        # ``{"status": "error", ...}``; the system endpoints keep their documented field holding
        # the reason instead (``status`` or ``result``, docs/decisions.md, A-16/A-39).
        assert isinstance(body, dict), (label, body)
        status = body.get("status", "error" if body.get("result") is False else None)
        assert isinstance(status, str) and status and status != "ok", (label, body)
        assert isinstance(body.get("description"), str) and body["description"], label
    elif (isinstance(body, dict) and body.get("result") is False
          and label.split()[1] not in RESULT_IS_THE_ANSWER):
        assert isinstance(body.get("description"), str) and body["description"], label


def test_junk_parameters_give_a_clear_error_on_every_endpoint(galileo: Harness) -> None:
    for method_path in sorted(routes.table()):
        _sweep(galileo, method_path)


def _sweep(galileo: Harness, method_path: tuple[str, str]) -> None:
    method, path = method_path
    before = galileo.runtime.status()
    points = galileo.runtime.store.points()
    for params, body in ((JUNK, None), ({}, JUNK)):
        response = galileo.http.request(method, path, params=params, json=body)
        content = response.json() if response.headers.get("content-type", "").startswith(
            "application/json") else None
        _check(response.status_code, content, f"{method} {path} {params or body}")
    broken = galileo.http.request(method, path, content=b"{not json",
                                  headers={"content-type": "application/json"})
    refused = broken.json()
    if routes.table()[method_path].result_errors:
        assert broken.status_code == 200 and refused["result"] is False
        assert "body" in refused["description"]
    else:
        assert broken.status_code == 400 and refused["status"] == "error"
    if path not in PARAMETERLESS:
        assert galileo.runtime.status().mode == before.mode, path
    elif galileo.runtime.status().mode == "mapping":
        galileo.runtime.cancel_mapping()
    else:
        galileo.ok("GET", "/navigation/stop_schedule_mode")
        galileo.runtime.advance(0.5)
    assert galileo.runtime.store.points() == points


def test_unknown_endpoint_and_method_are_errors_in_shape(galileo: Harness) -> None:
    missing = galileo.get("/navigation/nothing_here")
    assert missing.status_code == 404 and missing.json()["status"] == "error"
    wrong = galileo.http.request("PATCH", "/api/v1/system/status")
    assert wrong.status_code == 405 and "GET" in wrong.json()["description"]
    array = galileo.http.request("POST", "/api/v1/navigation/start_nav_task", json=[1, 2])
    assert array.status_code == 400
