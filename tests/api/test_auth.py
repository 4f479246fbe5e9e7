"""The native API off loopback (issue #37 item 7): every route and the WebSocket need a valid
token, a viewer only reads, failed logins are slowed down, sessions work by cookie, and neither a
password nor a token is ever logged or stored in clear. Over real HTTP and a real WebSocket."""

from __future__ import annotations

import json
import logging
import re
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest
from websockets.exceptions import InvalidStatus
from websockets.sync.client import connect

from polynav.api.auth_gate import PUBLIC_PATHS
from polynav.api.auth_passwords import hash_password
from tests.api.auth_site import PASSWORDS, TEST_HASHER, AuthSite, auth_site
from tests.api.test_openapi import DECLARED

LOGIN_OPERATIONS = {
    "login": {"200", "400", "401", "422", "429", "500"},
    "logout": {"204", "401", "500"},
    "get_me": {"200", "401", "500"},
}
READS = {"get", "head", "options"}


@pytest.fixture
def site(tmp_path: Path) -> Iterator[AuthSite]:
    with auth_site(tmp_path) as one:
        yield one


def _operations(site: AuthSite) -> list[tuple[str, str, str]]:
    """(operation id, method, a concrete path) of every operation in the document."""
    with site.client() as http:
        document = http.get("/openapi.json").json()
    return [
        (op["operationId"], method, re.sub(r"\{[^}]+\}", "initial", path))
        for path, item in document["paths"].items()
        for method, op in item.items()
    ]


def _error_code(answer: httpx.Response) -> str:
    return str(answer.json()["error"]["code"])


def test_the_document_declares_the_schemes_and_401_everywhere_403_on_writes(
    site: AuthSite,
) -> None:
    with site.client() as http:
        document = http.get("/openapi.json").json()
    schemes = document["components"]["securitySchemes"]
    assert schemes["bearer"] == {"type": "http", "scheme": "bearer",
                                 "description": "the token of POST /api/login"}
    assert (schemes["session"]["type"], schemes["session"]["in"]) == ("apiKey", "cookie")
    seen = set()
    for path, item in document["paths"].items():
        for method, op in item.items():
            seen.add(op["operationId"])
            declared = set(op["responses"])
            if path == "/api/login":
                assert op["security"] == []
                assert declared == LOGIN_OPERATIONS["login"]
                continue
            assert op["security"] == [{"bearer": []}, {"session": []}]
            expected = set(DECLARED.get(op["operationId"], LOGIN_OPERATIONS.get(
                op["operationId"], set()))) | {"401"}
            if method not in READS and path != "/api/logout":
                expected.add("403")
            assert declared == expected, op["operationId"]
    assert seen == set(DECLARED) | set(LOGIN_OPERATIONS)


def test_every_operation_refuses_a_request_without_a_valid_token(site: AuthSite) -> None:
    operator = site.login("olga")
    operations = _operations(site)
    assert len(operations) == len(DECLARED) + len(LOGIN_OPERATIONS)
    with site.client() as anonymous, site.client("not-a-token") as forged, \
            site.client(operator) as allowed:
        for operation_id, method, path in operations:
            if path in PUBLIC_PATHS:
                continue
            body = None if method in READS else {}
            for http in (anonymous, forged):
                answer = http.request(method, path, json=body)
                assert answer.status_code == 401, (operation_id, answer.text)
                assert _error_code(answer) == "unauthorized"
                assert answer.headers["www-authenticate"].startswith("Bearer")
            if method not in READS:  # refused before its body is even parsed
                answer = anonymous.request(method, path, content=b"{",
                                           headers={"content-type": "application/json"})
                assert answer.status_code == 401, operation_id
            if operation_id != "logout":  # that one would end the operator's token
                answer = allowed.request(method, path, json=body)
                assert answer.status_code not in (401, 403), (operation_id, answer.text)


def test_a_viewer_reads_but_every_write_is_403(site: AuthSite) -> None:
    viewer = site.login("victor")
    with site.client(viewer) as http:
        for operation_id, method, path in _operations(site):
            if path in PUBLIC_PATHS or operation_id == "logout":
                continue
            answer = http.request(method, path, json=None if method in READS else {})
            if method in READS:
                assert answer.status_code not in (401, 403), (operation_id, answer.text)
            else:
                assert answer.status_code == 403, (operation_id, answer.text)
                assert _error_code(answer) == "forbidden"
        assert http.post("/api/estop", json={"on": True}).status_code == 403
        assert http.get("/api/status").status_code == 200
        assert http.get("/api/me").json() == {"name": "victor", "role": "viewer"}
        assert http.post("/api/logout").status_code == 204  # a viewer may log out
        assert http.get("/api/status").status_code == 401


def test_an_operator_drives(site: AuthSite) -> None:
    with site.client(site.login("olga")) as http:
        assert http.post("/api/estop", json={"on": True}).status_code == 200
        assert http.get("/api/status").json()["estop"]["software"] is True
        assert http.get("/api/me").json() == {"name": "olga", "role": "operator"}


def test_ten_wrong_passwords_in_a_row_are_slowed_down(site: AuthSite) -> None:
    wrong = {"name": "olga", "password": "guess"}
    right = {"name": "olga", "password": PASSWORDS["olga"]}
    with site.client() as http:
        codes = [http.post("/api/login", json=wrong).status_code for _ in range(10)]
        assert codes == [401] * 5 + [429] * 5
        locked = http.post("/api/login", json=right)  # even the right one waits
        assert locked.status_code == 429
        assert _error_code(locked) == "too_many_attempts"
        assert locked.headers["retry-after"] == "1"
        assert site.service.limiter.failures("user:olga") == 5  # refusals are not counted
        # Each further failure doubles the wait: 1 s, 2 s, 4 s.
        for wait in (1, 2, 4):
            site.limiter_clock.now += wait
            assert http.post("/api/login", json=wrong).status_code == 401
            refused = http.post("/api/login", json=right)
            assert (refused.status_code, refused.headers["retry-after"]) == (429, str(2 * wait))
        site.limiter_clock.now += 8
        assert http.post("/api/login", json=right).status_code == 200
        assert site.service.limiter.failures("user:olga") == 0
        assert [http.post("/api/login", json=wrong).status_code for _ in range(5)] == [401] * 5


def test_failures_count_per_address_across_names(site: AuthSite) -> None:
    with site.client() as http:
        for name in ("olga", "victor", "olga", "victor", "nobody"):
            assert http.post("/api/login", json={"name": name, "password": "x"}).status_code \
                == 401
        answer = http.post("/api/login", json={"name": "victor",
                                               "password": PASSWORDS["victor"]})
        assert answer.status_code == 429  # this address guessed five times in a row
        assert site.service.limiter.failures("user:victor") == 2


def test_a_cookie_session_and_logout(site: AuthSite) -> None:
    with site.client() as http:
        answer = http.post("/api/login", json={"name": "olga", "password": PASSWORDS["olga"]})
        cookie = answer.headers["set-cookie"]
        token = answer.json()["token"]
        assert cookie.startswith(f"polynav_session={token};")
        assert {"httponly", "samesite=strict", "path=/api", "max-age=43200"} <= {
            part.strip().lower() for part in cookie.split(";")}
        assert http.get("/api/me").json()["name"] == "olga"  # the jar sends the cookie
        assert http.put("/api/settings", json={}).status_code == 200
        assert http.post("/api/logout").status_code == 204
        assert http.get("/api/me").status_code == 401
    with site.client(token) as http:
        assert http.get("/api/status").status_code == 401  # the token itself is revoked


def test_a_token_expires_and_a_new_password_or_removal_ends_it(site: AuthSite) -> None:
    token = site.login("olga")
    with site.client(token) as http:
        site.wall_clock.now += 12 * 3600 - 1
        assert http.get("/api/status").status_code == 200
        site.wall_clock.now += 1
        assert http.get("/api/status").status_code == 401
    token = site.login("olga")
    site.store.set_password("olga", hash_password("a new one", TEST_HASHER))
    with site.client(token) as http:
        assert http.get("/api/status").status_code == 401
    token = site.login("victor")
    site.store.remove_user("victor")
    with site.client(token) as http:
        assert http.get("/api/status").status_code == 401


def _ws_url(site: AuthSite, query: str = "") -> str:
    return site.url.replace("http://", "ws://") + "/api/ws" + query


@pytest.mark.parametrize("headers", [None, {"Authorization": "Bearer forged"},
                                     {"Cookie": "polynav_session=forged"}])
def test_the_websocket_refuses_a_handshake_without_a_valid_token(
    site: AuthSite, headers: dict[str, str] | None
) -> None:
    with pytest.raises(InvalidStatus) as refused:
        connect(_ws_url(site, "?token=forged" if headers else ""),
                additional_headers=headers, open_timeout=5.0)
    assert refused.value.response.status_code == 401
    assert json.loads(refused.value.response.body or b"{}")["error"]["code"] == "unauthorized"


@pytest.mark.parametrize("how", ["query", "bearer", "cookie"])
@pytest.mark.parametrize("name", ["olga", "victor"])
def test_the_websocket_streams_to_a_user_with_a_token(site: AuthSite, how: str,
                                                      name: str) -> None:
    token = site.login(name)
    headers: dict[str, Any] = {"bearer": {"Authorization": f"Bearer {token}"},
                               "cookie": {"Cookie": f"polynav_session={token}"}}.get(how, {})
    query = f"?token={token}" if how == "query" else ""
    with connect(_ws_url(site, query), additional_headers=headers, open_timeout=5.0) as ws:
        assert json.loads(ws.recv(timeout=5.0))["type"] == "status"


def test_neither_a_password_nor_a_token_is_logged_or_stored_in_clear(
    site: AuthSite, caplog: pytest.LogCaptureFixture
) -> None:
    caplog.set_level(logging.DEBUG)
    with site.client() as http:
        http.post("/api/login", json={"name": "olga", "password": "a wrong one"})
        token = http.post("/api/login", json={"name": "olga",
                                              "password": PASSWORDS["olga"]}).json()["token"]
        http.get("/api/status", headers={"Authorization": f"Bearer {token}"})
        http.get("/api/status", headers={"Authorization": "Bearer forged-token-xyz"})
    with connect(_ws_url(site, f"?token={token}"), open_timeout=5.0) as ws:
        ws.recv(timeout=5.0)
    # What the server side logs (the test's own HTTP and WebSocket clients log their headers).
    clients = ("httpx", "httpcore", "websockets.client")
    server_log = "\n".join(record.getMessage() for record in caplog.records
                           if not record.name.startswith(clients))
    assert "failed login as 'olga'" in server_log and "logged in" in server_log
    for secret in (PASSWORDS["olga"], "a wrong one", token, "forged-token-xyz"):
        assert secret not in server_log
    site.store.close()  # checkpoints the write-ahead log into site.db
    stored = b"".join(path.read_bytes() for path in site.store.data_dir.glob("site.db*"))
    assert b"$argon2id$" in stored
    for secret in (PASSWORDS["olga"], PASSWORDS["victor"], token):
        assert secret.encode() not in stored
