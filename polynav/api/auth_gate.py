"""The gate in front of the native API when it asks for a login, and what the document says.

A pure ASGI middleware, so it sees every HTTP request and every WebSocket handshake before
routing: deny by default. Open without a token are only ``/api/login``, the API's own
description (``/openapi.json``, ``/docs``, ``/redoc``) and the web console's static files
(``/``, ``/web/...``); everything else, routes added later and
unknown paths included, needs a valid token (401 otherwise), and a ``viewer`` may only read:
GET, HEAD, OPTIONS, the WebSocket's stream, and ``POST /api/logout`` (403 otherwise). Checking
before routing means a request without a token learns nothing, not even whether its body
parses or its path exists.

The token is looked up in a worker thread: the site store may be busy with a long write (a map
saved), and the event loop must not wait for it.

The OpenAPI document then declares the two ways to present a token (HTTP bearer, the session
cookie) and, on every operation, 401, and 403 on every operation a viewer may not call.
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Callable
from typing import Any

from fastapi import FastAPI
from fastapi.responses import JSONResponse
from starlette.requests import HTTPConnection
from starlette.types import ASGIApp, Receive, Scope, Send
from starlette.websockets import WebSocket

from polynav.api.auth import SESSION_COOKIE, LoginService, presented_token
from polynav.api.config import ApiConfig
from polynav.api.errors import error_body
from polynav.api.routes import auth as auth_routes
from polynav.store.site_store import SiteStore
from polynav.store.user_tables import UserRecord

log = logging.getLogger(__name__)

#: Paths served without a token.
PUBLIC_PATHS = frozenset({"/api/login", "/openapi.json", "/docs", "/docs/oauth2-redirect",
                          "/redoc", "/"})
#: Path prefixes served without a token: the web console's static files (its page at ``/``
#: shows the login form, so it must load before one; it holds no data).
PUBLIC_PREFIXES = ("/web/",)
#: Methods a viewer may use.
READ_METHODS = frozenset({"GET", "HEAD", "OPTIONS"})
#: Writes any user may make.
ANY_ROLE = frozenset({("POST", "/api/logout")})
#: The roles that may write.
WRITERS = frozenset({"operator"})

_UNAUTHORIZED = "log in first: POST /api/login, then send 'Authorization: Bearer <token>'"


def is_public(path: str) -> bool:
    """Whether ``path`` is served without a token."""
    return path in PUBLIC_PATHS or path.startswith(PUBLIC_PREFIXES)


def may(user: UserRecord, method: str, path: str) -> bool:
    """Whether ``user`` may make this request (a WebSocket handshake counts as a GET)."""
    return user.role in WRITERS or method in READ_METHODS or (method, path) in ANY_ROLE


class AuthGate:
    """ASGI middleware: pass a request on only with a valid token its user's role allows; the
    user goes to ``request.state.user``."""

    def __init__(self, app: ASGIApp, service: LoginService) -> None:
        self.app = app
        self.service = service

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] not in ("http", "websocket") or is_public(scope["path"]):
            await self.app(scope, receive, send)
            return
        websocket = scope["type"] == "websocket"
        method = "GET" if websocket else str(scope["method"])
        token = presented_token(HTTPConnection(scope), query=websocket)
        user = None
        if token is not None:
            store = scope["app"].state.store
            user = await asyncio.to_thread(self.service.user_of, store, token)
        if user is None:
            log.info("refused %s %s: no valid token", method, scope["path"])
            await _refuse(scope, receive, send, 401, "unauthorized",
                          _UNAUTHORIZED if token is None else "the token is unknown or expired")
            return
        if not may(user, method, scope["path"]):
            log.info("refused %s %s to %r: a %s only reads", method, scope["path"], user.name,
                     user.role)
            await _refuse(scope, receive, send, 403, "forbidden",
                          f"user {user.name!r} is a {user.role}: it may only read")
            return
        scope.setdefault("state", {})["user"] = user
        await self.app(scope, receive, send)


async def _refuse(scope: Scope, receive: Receive, send: Send, status: int, code: str,
                  message: str) -> None:
    headers = {"WWW-Authenticate": 'Bearer realm="polynav"'} if status == 401 else None
    answer = JSONResponse(error_body(code, message), status_code=status, headers=headers)
    if scope["type"] == "http":
        await answer(scope, receive, send)
        return
    websocket = WebSocket(scope, receive, send)
    if "websocket.http.response" in scope.get("extensions", {}):
        await websocket.send_denial_response(answer)  # the handshake answered 401 / 403
    else:
        await websocket.close(code=1008, reason=message[:120])


def _error(description: str) -> dict[str, Any]:
    return {"description": description, "content": {
        "application/json": {"schema": {"$ref": "#/components/schemas/ErrorOut"}}}}


SECURITY_SCHEMES = {
    "bearer": {"type": "http", "scheme": "bearer",
               "description": "the token of POST /api/login"},
    "session": {"type": "apiKey", "in": "cookie", "name": SESSION_COOKIE,
                "description": "the console's session cookie, set by POST /api/login"},
}


def declare_security(document: dict[str, Any]) -> dict[str, Any]:
    """Add the security schemes to an OpenAPI document, and to each operation its security
    (either scheme) and its 401 and, if a viewer may not call it, 403."""
    document.setdefault("components", {})["securitySchemes"] = SECURITY_SCHEMES
    for path, item in document["paths"].items():
        for method, operation in item.items():
            if path in PUBLIC_PATHS:
                operation["security"] = []
                continue
            operation["security"] = [{"bearer": []}, {"session": []}]
            answers = operation["responses"]
            answers["401"] = _error("no token, or an unknown or expired one "
                                    "(code `unauthorized`)")
            if method.upper() not in READ_METHODS and (method.upper(), path) not in ANY_ROLE:
                answers["403"] = _error("a viewer may only read (code `forbidden`)")
    return document


def install_login(app: FastAPI, config: ApiConfig) -> None:
    """Make ``app`` ask for a login: the login routes, the gate, and the document's security."""
    service = LoginService(config.session_ttl)
    app.state.login = service
    app.include_router(auth_routes.router)
    app.add_middleware(AuthGate, service=service)
    build: Callable[[], dict[str, Any]] = app.openapi

    def openapi() -> dict[str, Any]:
        if app.openapi_schema is None:
            app.openapi_schema = declare_security(build())
        return app.openapi_schema

    app.openapi = openapi  # type: ignore[method-assign]


def login_refusal(config: ApiConfig, store: SiteStore) -> str | None:
    """Why ``polynav run`` must not start: it would ask for a login nobody can give."""
    if not config.login_required or store.user_count() > 0:
        return None
    return (f"--host {config.host} is not loopback, so the native API asks for a login, and "
            f"the site in {store.data_dir} has no user yet; add one first: polynav users add "
            f"NAME --role operator --data {store.data_dir}")
