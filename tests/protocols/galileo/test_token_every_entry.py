"""With token checking on, every entry of both HTTP lists and every WebSocket entry is refused
without a valid token, as documented (galileo-http-a §1.4: HTTP 401 and ``{"status": "error",
"description": "invalid token"}``; the WebSocket handshake gets the same 401), and the refused
request changes nothing. ``/token`` itself is the one entry served without one (it is how a
client gets one).

One server for the whole module (each case only sends refused requests); the digest of
:mod:`tests.protocols.galileo.state` is compared around each entry.
"""

from __future__ import annotations

import json
from collections.abc import Iterator
from typing import Any

import pytest
from websockets.exceptions import InvalidStatus
from websockets.sync.client import connect

from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds.world import World
from tests.protocols.galileo import spec
from tests.protocols.galileo.conftest import Harness, galileo_config, serving
from tests.protocols.galileo.state import digest
from tests.protocols.galileo.test_coverage import TODO

REFUSAL = {"status": "error", "description": "invalid token"}
PUBLIC = {"GET /api/v1/token"}
#: Concrete URLs for entries whose path ends in a parameter (A-20) or names any topic.
CONCRETE = {"/api/v1/system/saved_images/": "/api/v1/system/saved_images/1683278160650",
            "/api/v1/system/saved_videos/": "/api/v1/system/saved_videos/1683278160650",
            "/{topicName}": "/tracked_pose"}
#: Plausible parameters, so that nothing but the token is missing.
PARAMS = {"map": "floor1", "path": "default", "index": "1", "map_name": "floor1",
          "path_name": "default", "id": "1", "name": "x", "level": "1", "port": "1",
          "x": "1", "y": "1", "theta": "0", "distance": "0.5", "angle": "0", "method": "0",
          "text": "hello", "volume": "50", "path_data": "1 1 0 0 0.1 0.1 0",
          "topic_name": "/galileo/status", "file_timestamp": "1683278160650"}
BAD_TOKENS: tuple[str | None, ...] = (None, "", "f" * 32, "not-a-token")


@pytest.fixture(scope="module")
def locked(world: World, tmp_path_factory: pytest.TempPathFactory) -> Iterator[Harness]:
    data = tmp_path_factory.mktemp("galileo-token") / "data"
    with SiteStore.open(data, seed_world=world) as store:
        runtime = RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False))
        with serving(runtime, galileo_config(require_token=True)) as g:
            yield g


def _url(key: str) -> tuple[str, str]:
    method, path = key.split(" @")[0].split(" ", 1)
    return method, CONCRETE.get(path, path)


def _http_refused(g: Harness, method: str, url: str) -> None:
    for token in BAD_TOKENS:
        query = dict(PARAMS) if token is None else {**PARAMS, "token": token}
        body: dict[str, Any] | None = None
        if method in ("POST", "PUT"):
            body = dict(PARAMS) if token is None else {**PARAMS, "token": token}
        response = g.http.request(method, url, params=query, json=body)
        assert response.status_code == 401, (method, url, token, response.text)
        assert response.json() == REFUSAL, (method, url, token)
    # A body that does not parse is refused as unauthenticated too (it could hold no token).
    broken = g.http.request(method, url, params={"token": "f" * 32}, content=b"{not json",
                            headers={"content-type": "application/json"})
    assert (broken.status_code, broken.json()) == (401, REFUSAL), (method, url, broken.text)


def _ws_refused(g: Harness, url: str) -> None:
    for token in BAD_TOKENS:
        query = "" if token is None else f"?token={token}"
        with pytest.raises(InvalidStatus) as refused:
            connect(f"ws://127.0.0.1:{g.server.ws_port}{url}{query}", open_timeout=20)
        response = refused.value.response
        assert response.status_code == 401, (url, token)
        assert json.loads(response.body) == REFUSAL


# the HTTP and WebSocket entries (what is not built yet: 404); the wire protocols have no token
@pytest.mark.parametrize("key", sorted(set(spec.ALL) - set(spec.WIRE) - TODO))
def test_every_entry_is_refused_without_a_valid_token(locked: Harness, key: str) -> None:
    method, url = _url(key)
    runtime: RobotRuntime = locked.runtime
    before = digest(runtime, locked.server)
    if key in PUBLIC:  # served without a token: it is how a client gets one
        reply = locked.ok(method, url, params={"username": "admin", "password": "admin"})
        assert reply["result"] is True
        return
    if key in spec.WS:
        _ws_refused(locked, url)
    else:
        _http_refused(locked, method, url)
    runtime.advance(0.5)  # anything a refused request had started would show by now
    assert digest(runtime, locked.server) == before, key


def test_a_valid_token_opens_the_same_entries(locked: Harness) -> None:
    """The control: the refusals above are the token's doing (a valid one is served)."""
    token = locked.ok("GET", "/token", params={"username": "admin", "password": "admin"})
    locked.token = token["token"]
    try:
        assert locked.ok("GET", "/system/galileo_status")["navStatus"] == 0
        with connect(f"ws://127.0.0.1:{locked.server.ws_port}/tracked_pose"
                     f"?token={locked.token}", open_timeout=20) as ws:
            assert "pose" in ws.recv(timeout=20)
    finally:
        locked.token = None
