"""Token auth (galileo-http-a E-01, §1.3–1.4): ``/token``, checking on and off, refusals."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from polynav.errors import ConfigError
from polynav.protocols.galileo import routes
from polynav.protocols.galileo.auth import ServiceSettings, load_settings
from polynav.runtime.robot_runtime import RobotRuntime
from tests.protocols.galileo.conftest import galileo_config, serving

COVERED = {
    "GET /api/v1/token": "test_token_is_issued_for_the_configured_credentials",
}


def _write_config(runtime: RobotRuntime, **values: object) -> Path:
    path = runtime.store.data_dir / "galileo" / "config.json"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps({**ServiceSettings().to_dict(), **values}), encoding="utf-8")
    return path


def test_token_is_issued_for_the_configured_credentials(runtime: RobotRuntime) -> None:
    _write_config(runtime, username="ops", password="s3cret", no_token_check=False)
    with serving(runtime) as g:
        for path in ("/token", "/api/v1/token"):
            body = g.ok("GET", path, params={"username": "ops", "password": "s3cret"})
            assert body["result"] is True
            assert len(body["token"]) == 32 and int(body["token"], 16) >= 0
        wrong = g.ok("GET", "/token", params={"username": "ops", "password": "nope"})
        assert wrong["result"] is False and wrong["token"] == ""
        missing = g.request("GET", "/token", params={"username": "ops"})
        assert missing.status_code == 400 and "password" in missing.json()["description"]


def test_checking_off_by_default_serves_without_a_token(runtime: RobotRuntime) -> None:
    with serving(runtime) as g:
        assert g.get("/system/status").status_code == 200


def test_token_accepted_in_query_json_body_and_form(runtime: RobotRuntime) -> None:
    _write_config(runtime, no_token_check=False)
    with serving(runtime) as g:
        token = g.ok("GET", "/token", params={"username": "admin", "password": "admin"})["token"]
        assert g.get("/system/status").status_code == 401
        assert g.get("/system/status", token="0" * 32).status_code == 401
        assert g.get("/system/status", token=token).status_code == 200
        # A POST/PUT carries it in the query or the body; a wrong one is refused either way.
        url = "/api/v1/system/status"
        assert g.http.request("GET", url, json={"token": token}).status_code == 200
        assert g.http.request("GET", url, data={"token": token}).status_code == 200
        assert g.http.request("GET", url, json={"token": "bad"}).status_code == 401


def test_require_token_forces_checking_whatever_config_json_says(runtime: RobotRuntime) -> None:
    with serving(runtime, galileo_config(require_token=True)) as g:
        refused = g.get("/system/galileo_status")
        assert refused.status_code == 401
        assert refused.json() == {"status": "error", "description": "invalid token"}
        g.token = g.ok("GET", "/token", params={"username": "admin", "password": "admin"})[
            "token"
        ]
        assert g.get("/system/galileo_status").status_code == 200


def test_every_endpoint_refuses_a_request_without_a_valid_token(runtime: RobotRuntime) -> None:
    before = runtime.status()
    with serving(runtime, galileo_config(require_token=True)) as g:
        for (method, path), endpoint in routes.table().items():
            if endpoint.public:
                continue
            for token in (None, "f" * 32):
                params = {} if token is None else {"token": token}
                response = g.http.request(method, path, params=params)
                assert response.status_code == 401, (method, path, response.text)
                assert response.json() == {"status": "error", "description": "invalid token"}
        after = runtime.status()
    assert (after.mode, after.attempt_id) == (before.mode, before.attempt_id)


def test_vendor_default_config_with_trailing_comma_loads(tmp_path: Path) -> None:
    path = tmp_path / "config.json"
    path.write_text('{\n "username": "admin",\n "password": "pw",\n "allow_update": true,\n'
                    ' "no_token_check": false,\n "auto_charge": false,\n}\n', encoding="utf-8")
    settings = load_settings(path)
    assert settings.password == "pw" and settings.no_token_check is False
    assert load_settings(tmp_path / "absent.json") == ServiceSettings()


@pytest.mark.parametrize("text", ["[1, 2]", "{not json", '{"no_token_check": "false"}'])
def test_bad_config_json_is_a_clear_config_error(tmp_path: Path, text: str) -> None:
    path = tmp_path / "config.json"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ConfigError, match="galileo.config_file"):
        load_settings(path)
