"""``polynav users`` and ``polynav run`` off loopback; when the API asks for a login; the user
tables of the site store."""

from __future__ import annotations

import io
import os
import subprocess
import sys
from pathlib import Path

import pytest

from polynav import users_cli
from polynav.api import ApiConfig, create_app
from polynav.cli import main
from polynav.errors import Conflict, InvalidRequest, NotFound
from polynav.store.site_store import SiteStore
from polynav.store.user_tables import ROLES
from tests.api.auth_site import TEST_HASHER
from tests.api.fakes import FakeRuntime
from tests.api.server import native_client

REPO = Path(__file__).resolve().parents[2]


def _users(data: Path, *args: str, stdin: str = "") -> int:
    old = sys.stdin
    sys.stdin = io.StringIO(stdin)
    try:
        return main(["users", *args, "--data", str(data)])
    finally:
        sys.stdin = old


def test_users_add_list_passwd_rm_round_trip(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    data = tmp_path / "data"
    assert _users(data, "add", "alice", "--role", "operator", "--password-stdin",
                  stdin="first secret\n") == 0
    assert _users(data, "add", "bob", "--password-stdin", stdin="bob's\n") == 0
    capsys.readouterr()
    assert _users(data, "list") == 0
    lines = [line.split("\t")[:2] for line in capsys.readouterr().out.splitlines()]
    assert lines == [["alice", "operator"], ["bob", "viewer"]]
    with SiteStore.open(data) as store:
        first = store.password_hash("alice")
        assert first is not None and first.startswith("$argon2id$")
        assert "first secret" not in first
    assert _users(data, "passwd", "alice", "--password-stdin", stdin="second secret\n") == 0
    assert _users(data, "add", "alice", "--password-stdin", stdin="x\n") == 1  # taken
    assert "already exists" in capsys.readouterr().err
    assert _users(data, "add", "carol", "--password-stdin", stdin="\n") == 2  # empty
    assert "must not be empty" in capsys.readouterr().err
    assert _users(data, "rm", "bob") == 0
    assert _users(data, "rm", "bob") == 1
    # The password set by the command line is the one the API takes.
    with SiteStore.open(data) as store:
        assert [u.name for u in store.users()] == ["alice"]
        assert not store.maps()  # users need no site: the directory was not seeded
        with native_client(FakeRuntime(store), auth=True) as http:
            refused = http.post("/api/login", json={"name": "alice",
                                                    "password": "first secret"})
            assert refused.status_code == 401
            granted = http.post("/api/login", json={"name": "alice",
                                                    "password": "second secret"})
            assert granted.json()["role"] == "operator"


def test_run_off_loopback_without_a_user_refuses_before_binding(tmp_path: Path) -> None:
    env = {**os.environ, "PYTHONPATH": str(REPO)}
    done = subprocess.run(
        [sys.executable, "-m", "polynav", "run", "--host", "0.0.0.0", "--port", "0",
         "--data", str(tmp_path / "data"), "--no-yunji", "--no-galileo", "--no-puwei",
         "--no-rosbridge"],
        capture_output=True, text=True, timeout=120, env=env, cwd=tmp_path,
    )
    assert done.returncode == 2, done.stdout + done.stderr
    assert "--host 0.0.0.0 is not loopback" in done.stderr
    assert "polynav users add NAME --role operator" in done.stderr
    assert "native API" not in done.stdout  # it never served


@pytest.mark.parametrize(("host", "auth", "required"), [
    ("127.0.0.1", None, False), ("127.0.0.2", None, False), ("::1", None, False),
    ("localhost", None, False), ("0.0.0.0", None, True), ("::", None, True),
    ("192.168.1.20", None, True), ("robot.local", None, True),
    ("127.0.0.1", True, True), ("0.0.0.0", False, False),
])
def test_a_login_is_required_exactly_off_loopback(
    host: str, auth: bool | None, required: bool
) -> None:
    assert ApiConfig(host=host, auth=auth).login_required is required


def test_on_loopback_the_api_stays_open_and_its_document_unchanged(
    fake_runtime: FakeRuntime,
) -> None:
    document = create_app(fake_runtime, ApiConfig(port=0)).openapi()
    assert "securitySchemes" not in document.get("components", {})
    assert "/api/login" not in document["paths"]
    assert all("security" not in op for item in document["paths"].values()
               for op in item.values())


def test_the_store_keeps_only_hashes_and_checks_its_input(tmp_path: Path) -> None:
    assert users_cli.ROLES == ROLES
    with SiteStore.open(tmp_path / "data") as store:
        hashed = TEST_HASHER.hash("pw")
        with pytest.raises(InvalidRequest):
            store.add_user("eve", "operator", "pw", "2026-01-01")  # not a hash
        with pytest.raises(InvalidRequest):
            store.add_user("eve", "admin", hashed, "2026-01-01")
        with pytest.raises(InvalidRequest):
            store.add_user(" eve", "viewer", hashed, "2026-01-01")
        store.add_user("eve", "viewer", hashed, "2026-01-01")
        with pytest.raises(Conflict):
            store.add_user("eve", "operator", hashed, "2026-01-01")
        with pytest.raises(NotFound):
            store.set_password("nobody", hashed)
        with pytest.raises(NotFound):
            store.add_token("f" * 64, "nobody", 0.0, 10.0)
        store.add_token("a" * 64, "eve", 0.0, 10.0)
        assert store.token_user("a" * 64, 9.9) == store.user("eve")
        assert store.token_user("a" * 64, 10.0) is None  # expired
        store.add_token("b" * 64, "eve", 20.0, 30.0)  # drops the expired one
        assert not store.remove_token("a" * 64)
        store.remove_user("eve")
        assert store.token_user("b" * 64, 21.0) is None  # went with its user


def test_a_building_off_loopback_without_a_user_refuses_too(tmp_path: Path) -> None:
    env = {**os.environ, "PYTHONPATH": str(REPO)}
    done = subprocess.run(
        [sys.executable, "-m", "polynav", "run", "--robots", "2", "--host", "0.0.0.0",
         "--port", "0", "--yunji-port", "0", "--yunji-http-port", "0",
         "--data", str(tmp_path / "data")],
        capture_output=True, text=True, timeout=120, env=env, cwd=tmp_path,
    )
    assert done.returncode == 2, done.stdout + done.stderr
    assert "--host 0.0.0.0 is not loopback" in done.stderr
    assert "native API" not in done.stdout
