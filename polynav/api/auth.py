"""Logins of the native API: who presents which token, and trading a password for a token.

The API asks for a login only when it listens beyond loopback (:attr:`ApiConfig.login_required
<polynav.api.config.ApiConfig.login_required>`; docs/auth.md). A login trades a name and a
password for a random token, valid ``session_ttl`` seconds; programs send it as ``Authorization:
Bearer <token>``, the console gets it in an HttpOnly, SameSite=Strict cookie, and the WebSocket
takes either or ``?token=`` (a browser cannot set headers on a WebSocket). The gate that checks
every request is :mod:`polynav.api.auth_gate`.

Neither a password nor a token is ever logged; the store keeps only their hashes
(:mod:`polynav.api.auth_passwords`).
"""

from __future__ import annotations

import datetime
import logging
import time
from collections.abc import Callable
from dataclasses import dataclass, field

from starlette.requests import HTTPConnection

from polynav.api.auth_limits import LoginLimiter
from polynav.api.auth_passwords import new_token, token_hash, verify_password
from polynav.store.site_store import SiteStore
from polynav.store.user_tables import UserRecord

log = logging.getLogger(__name__)

#: The console's session cookie: the token, HttpOnly (no script reads it), SameSite=Strict (no
#: other site's page sends it), on ``/api`` only.
SESSION_COOKIE = "polynav_session"
#: Longest token looked up; ours are 43 characters.
_MAX_TOKEN = 256


class LoginDenied(Exception):
    """Wrong name or password (which one is not said)."""


class LoginThrottled(Exception):
    """Too many failed logins in a row: try again in ``wait`` seconds."""

    def __init__(self, wait: float) -> None:
        super().__init__(f"too many failed logins: try again in {wait:.0f} s")
        self.wait = wait


@dataclass(frozen=True, slots=True)
class Granted:
    """A successful login: the user, its new token and how long the token lives [s]."""

    user: UserRecord
    token: str
    expires_in: float


def presented_token(conn: HTTPConnection, *, query: bool = False) -> str | None:
    """The token a request presents: ``Authorization: Bearer``, else the session cookie, else
    (with ``query``, for the WebSocket) ``?token=``."""
    scheme, _, credentials = conn.headers.get("authorization", "").partition(" ")
    if scheme.lower() == "bearer" and credentials.strip():
        return credentials.strip()
    cookie = conn.cookies.get(SESSION_COOKIE)
    if cookie:
        return cookie
    if query:
        return conn.query_params.get("token") or None
    return None


def now_iso() -> str:
    """The wall date-time a user is created at, to the second."""
    return datetime.datetime.now(datetime.UTC).replace(microsecond=0).isoformat()


@dataclass(slots=True)
class LoginService:
    """Logins, tokens and the limiter of failed attempts of one app.

    Attributes:
        session_ttl: how long a token lives [s wall].
        limiter: failed logins per user and per client address.
        clock: wall seconds since the epoch (token expiry); tests pass a fake one.
    """

    session_ttl: float
    limiter: LoginLimiter = field(default_factory=LoginLimiter)
    clock: Callable[[], float] = time.time

    def user_of(self, store: SiteStore, token: str | None) -> UserRecord | None:
        """The user whose valid (known, unexpired) token this is; ``None`` otherwise."""
        if not token or len(token) > _MAX_TOKEN:
            return None
        return store.token_user(token_hash(token), self.clock())

    def login(self, store: SiteStore, name: str, password: str, client: str) -> Granted:
        """Check a name and password from ``client`` (its address) and issue a token.

        Blocks for the password hash (tenths of a second): call it from a worker thread.

        Raises:
            LoginThrottled: too many failures in a row for this name or this address; the
                password was not even checked.
            LoginDenied: an unknown name or a wrong password.
        """
        keys = (f"user:{name}", f"addr:{client}")
        wait = self.limiter.attempt(keys)
        if wait > 0.0:
            log.warning("login as %r from %s refused for %.1f s more: too many failures",
                        name, client, wait)
            raise LoginThrottled(wait)
        if not verify_password(store.password_hash(name), password):
            log.warning("failed login as %r from %s", name, client)
            raise LoginDenied("wrong name or password")
        user = store.user(name)
        self.limiter.succeeded(keys)
        token = new_token()
        now = self.clock()
        store.add_token(token_hash(token), user.name, now, now + self.session_ttl)
        log.info("user %r (%s) logged in from %s", user.name, user.role, client)
        return Granted(user, token, self.session_ttl)

    def logout(self, store: SiteStore, token: str | None) -> None:
        """Revoke a token (nothing if there is none)."""
        if token and len(token) <= _MAX_TOKEN and store.remove_token(token_hash(token)):
            log.info("a token was revoked (logout)")
