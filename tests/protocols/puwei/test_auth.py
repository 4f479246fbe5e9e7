"""Login (puwei-api §4), the token on every protected endpoint, and device discovery by HTTP."""

from __future__ import annotations

from polynav.protocols.puwei import routes
from tests.protocols.puwei.conftest import Harness, envelope, refused

COVERED = {
    "POST /api/user/login": "test_login_puts_the_token_in_the_authorization_response_header",
    "GET /api/devices": "test_devices_lists_this_robots_address_without_a_token",
}

#: Every protected endpoint, with example path parameters.
PROTECTED = sorted(
    (e.method, e.path.replace(":name", "floor1").replace(":value", "0.5"))
    for e in routes.table() if not e.public
)


def test_login_puts_the_token_in_the_authorization_response_header(puwei: Harness) -> None:
    response = puwei.http.post("/api/user/login", json={"username": "admin",
                                                        "password": "admin"})
    body = envelope(response)
    assert body["code"] == 0
    token = response.headers["authorization"]
    assert len(token) == 32 and token != puwei.token
    # The token, sent as is (no "Bearer"), opens the protected endpoints.
    ok = envelope(puwei.http.get("/api/roslaunch/status", headers={"authorization": token}))
    assert ok["code"] == 0 and ok["data"] == 0


def test_login_with_a_wrong_password_gives_no_token(puwei: Harness) -> None:
    response = puwei.http.post("/api/user/login", json={"username": "admin", "password": "x"})
    body = refused(response)
    assert body["code"] == 402
    assert "authorization" not in response.headers


def test_login_refuses_malformed_bodies(puwei: Harness) -> None:
    for body in (b"{not json", b"[1, 2]", b'{"username": 1, "password": "admin"}',
                 b'{"username": "admin"}', b"", b'{"username": "admin", "password": NaN}'):
        response = puwei.http.post("/api/user/login", content=body,
                                   headers={"content-type": "application/json"})
        assert refused(response)["code"] == 2, body
        assert "authorization" not in response.headers


def test_devices_lists_this_robots_address_without_a_token(puwei: Harness) -> None:
    body = envelope(puwei.http.get("/api/devices"))
    assert body["code"] == 0
    assert body["data"] == ["127.0.0.1"]


def test_every_protected_endpoint_refuses_without_a_valid_token(puwei: Harness) -> None:
    before = (puwei.runtime.status().mode, puwei.runtime.settings())
    for token in (None, "", "0123456789abcdef0123456789abcdef", puwei.token + " x"):
        headers = {} if token is None else {"authorization": token}
        for method, path in PROTECTED:
            response = puwei.http.request(method, path, headers=headers, content=b"{bad json")
            assert refused(response)["code"] == 401, (method, path, token)
    assert (puwei.runtime.status().mode, puwei.runtime.settings()) == before
