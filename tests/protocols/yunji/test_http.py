"""The legacy HTTP form of the Yunji API (8808 on the robot; an ephemeral port here): the same
commands as HTTP GET paths, the same JSON bodies.

Simulated time advances only when a test calls ``runtime.advance`` (see conftest).
"""

from __future__ import annotations

import http.client
import json
import urllib.error
import urllib.request
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import pytest

from polynav.protocols.yunji import YunjiConfig
from polynav.runtime.robot_runtime import RobotRuntime
from tests.protocols.yunji.conftest import Harness, serving


@pytest.fixture
def web(runtime: RobotRuntime) -> Iterator[Harness]:
    with serving(runtime, YunjiConfig(port=0, http_port=0)) as h:
        yield h


def _get(h: Harness, target: str) -> tuple[int, str, dict[str, Any]]:
    port = h.server.http_port
    assert port is not None
    with urllib.request.urlopen(f"http://127.0.0.1:{port}{target}", timeout=30) as reply:
        body = json.loads(reply.read())
        return reply.status, reply.headers["content-type"], body


def test_robot_status_over_http_is_the_tcp_reply(web: Harness) -> None:
    status, content_type, body = _get(web, "/api/robot_status?uuid=h1")
    assert (status, content_type) == (200, "application/json")
    assert {k: body[k] for k in ("type", "command", "uuid", "status", "error_message")} == {
        "type": "response", "command": "/api/robot_status", "uuid": "h1", "status": "OK",
        "error_message": ""}
    assert body["results"]["current_floor"] == 1 and body["results"]["move_status"] == "idle"


def test_a_move_and_a_cancel_over_http(web: Harness) -> None:
    _, _, moved = _get(web, "/api/move?marker=lobby")
    assert moved["status"] == "OK" and len(moved["task_id"]) == 32
    web.runtime.advance(1.0)
    assert _get(web, "/api/robot_status")[2]["results"]["move_status"] == "running"
    assert _get(web, "/api/move?marker=kitchen")[2]["status"] == "REQUEST_DENIED"
    assert _get(web, "/api/move/cancel")[2]["status"] == "OK"
    assert _get(web, "/api/robot_status")[2]["results"]["move_status"] == "canceled"


def test_bad_requests_over_http_get_the_dialect_errors(web: Harness) -> None:
    assert _get(web, "/api/no_such_thing")[2]["status"] == "INVALID_REQUEST"
    bad = _get(web, "/api/move?marker=%ZZ&uuid=u9")[2]
    assert (bad["status"], bad["command"], bad["uuid"]) == ("INVALID_REQUEST", "/api/move", "u9")
    assert _get(web, "/api/move?marker=nowhere")[2]["error_message"] == "Marker Not Found"
    streams = _get(web, "/api/request_data?topic=robot_status")[2]
    assert streams["status"] == "REQUEST_DENIED" and "TCP" in streams["error_message"]
    port = web.server.http_port
    request = urllib.request.Request(f"http://127.0.0.1:{port}/api/robot_status", method="POST")
    with pytest.raises(urllib.error.HTTPError) as refused:
        urllib.request.urlopen(request, timeout=30)
    assert refused.value.code == 405
    refused.value.close()


def test_an_oversized_request_is_refused_and_the_listener_keeps_serving(web: Harness) -> None:
    port = web.server.http_port
    assert port is not None
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
    try:
        conn.request("GET", "/api/robot_status?pad=" + "x" * 200_000)
        reply = conn.getresponse()
        body = reply.read()
        assert reply.status >= 400 or json.loads(body)["status"] == "INVALID_REQUEST"
    except (ConnectionError, http.client.HTTPException):
        pass  # the parser may drop the connection instead of answering
    finally:
        conn.close()
    assert _get(web, "/api/robot_info")[2]["status"] == "OK"


def test_many_http_clients_at_once(web: Harness) -> None:
    with ThreadPoolExecutor(max_workers=16) as pool:
        replies = list(pool.map(lambda n: _get(web, f"/api/robot_status?uuid={n}"), range(64)))
    assert sorted(int(body["uuid"]) for _, _, body in replies) == list(range(64))
    assert all(body["status"] == "OK" for _, _, body in replies)
