"""Puwei login: ``POST /api/user/login`` and the tokens it hands out (puwei-api §4).

The token goes back in the ``authorization`` *response* header (the body's ``data`` is empty)
and comes again, as is and without ``Bearer``, in the ``authorization`` request header of every
other call, and as ``token=`` in the WebSocket's query (A3). A token is 32 random hex digits,
valid until the server stops or ``token_ttl`` passes (wall clock: a token's life is transport,
not robot behaviour). Tokens and passwords are never logged (STYLE R9).
"""

from __future__ import annotations

import hmac
import logging
import secrets
import threading
import time
from collections.abc import Callable

from starlette.responses import Response

from polynav.errors import InvalidRequest
from polynav.protocols.puwei import errors
from polynav.protocols.puwei.context import Context
from polynav.protocols.puwei.endpoint import RouteList
from polynav.protocols.puwei.http import AUTH_HEADER, envelope
from polynav.protocols.puwei.request import PuweiRequest, type_name

log = logging.getLogger(__name__)

ROUTES = RouteList()

#: Tokens kept at most; the oldest goes first (a client that logs in on every call must not
#: grow the book without end).
MAX_TOKENS = 1024


class TokenBook:
    """The credentials and the tokens given out; implements :class:`~.context.Tokens`."""

    def __init__(self, *, username: str, password: str, ttl: float = 0.0,
                 now: Callable[[], float] = time.monotonic) -> None:
        self._username = username
        self._password = password
        self._ttl = ttl
        self._now = now
        self._tokens: dict[str, float] = {}  # token -> when given [s]
        self._lock = threading.Lock()

    def login(self, username: str, password: str) -> str:
        """A new token for the right credentials.

        Raises:
            LoginFailed: wrong user name or password.
        """
        # Constant-time comparisons: the answer's timing must not tell how much matched.
        user_ok = hmac.compare_digest(username.encode("utf-8"), self._username.encode("utf-8"))
        pass_ok = hmac.compare_digest(password.encode("utf-8"), self._password.encode("utf-8"))
        if not (user_ok and pass_ok):
            raise errors.LoginFailed()
        token = secrets.token_hex(16)
        with self._lock:
            self._tokens[token] = self._now()
            while len(self._tokens) > MAX_TOKENS:
                del self._tokens[next(iter(self._tokens))]
        return token

    def valid(self, token: str | None) -> bool:
        """Whether ``token`` is one the login gave out and it has not expired."""
        if not token:
            return False
        with self._lock:
            given = self._tokens.get(token.strip())
        if given is None:
            return False
        return self._ttl <= 0 or self._now() - given <= self._ttl


@ROUTES.post("/api/user/login", inline=True, public=True)
def login(ctx: Context, request: PuweiRequest) -> Response:
    """``{"username", "password"}`` -> the token in the ``authorization`` response header."""
    body = request.json_object()
    fields: dict[str, str] = {}
    for key in ("username", "password"):
        value = body.get(key)
        if not isinstance(value, str):
            raise InvalidRequest(key, f"a string is required, got {type_name(value)}")
        fields[key] = value
    tokens = ctx.tokens
    assert isinstance(tokens, TokenBook)
    token = tokens.login(fields["username"], fields["password"])
    log.info("puwei: %s logged in", fields["username"])
    reply = envelope({})
    reply.headers[AUTH_HEADER] = token
    # A browser client reads the header only when CORS exposes it (puwei-api §4.2).
    reply.headers["access-control-expose-headers"] = AUTH_HEADER
    return reply
