"""A site with one operator and one viewer, served by an app that asks for a login, over real
HTTP on 127.0.0.1. Passwords are hashed with argon2id at test-sized cost (the server verifies
any argon2 hash at the cost written in it), so a login takes milliseconds, not tenths."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import httpx
from argon2 import PasswordHasher

from polynav.api import ApiConfig, create_app
from polynav.api.auth import LoginService
from polynav.api.auth_passwords import hash_password
from polynav.store.site_store import SiteStore
from polynav.worlds import load_world
from tests.api.fakes import FakeRuntime
from tests.api.server import ServerThread

TEST_HASHER = PasswordHasher(time_cost=1, memory_cost=1024, parallelism=1)
PASSWORDS = {"olga": "correct horse battery staple", "victor": "viewer's own passphrase"}
ROLES = {"olga": "operator", "victor": "viewer"}


class FakeClock:
    """Seconds that move only when told to."""

    def __init__(self, start: float) -> None:
        self.now = start

    def __call__(self) -> float:
        return self.now


@dataclass
class AuthSite:
    store: SiteStore
    server: ServerThread
    service: LoginService
    limiter_clock: FakeClock
    wall_clock: FakeClock

    @property
    def url(self) -> str:
        return self.server.url

    def client(self, token: str | None = None) -> httpx.Client:
        headers = {"Authorization": f"Bearer {token}"} if token is not None else None
        return httpx.Client(base_url=self.url, timeout=10.0, headers=headers)

    def login(self, name: str) -> str:
        with self.client() as http:
            answer = http.post("/api/login", json={"name": name, "password": PASSWORDS[name]})
        assert answer.status_code == 200, answer.text
        return str(answer.json()["token"])


def add_users(store: SiteStore) -> None:
    for name, password in PASSWORDS.items():
        store.add_user(name, ROLES[name], hash_password(password, TEST_HASHER), "2026-01-01")


@contextlib.contextmanager
def auth_site(root: Path) -> Iterator[AuthSite]:
    """The demo site with olga (operator) and victor (viewer), served with logins required;
    the limiter and the token expiry run on fake clocks."""
    store = SiteStore.open(root / "data", seed_world=load_world("demo"))
    add_users(store)
    app = create_app(FakeRuntime(store), ApiConfig(port=0, auth=True))
    service: LoginService = app.state.login
    limiter_clock, wall_clock = FakeClock(1000.0), FakeClock(1.8e9)
    service.limiter.clock = limiter_clock
    service.clock = wall_clock
    server = ServerThread(app).start()
    try:
        yield AuthSite(store, server, service, limiter_clock, wall_clock)
    finally:
        server.stop()
        store.close()
