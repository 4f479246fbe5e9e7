"""The Puwei HTTP transport (port 8080): read the request, check the token, dispatch, answer.

One Starlette route per endpoint; the WebSocket at ``/api/ws`` shares the port (puwei-api §1,
A1: the path is polynav's choice, docs/puwei.md). Every JSON reply is the envelope ``{"code",
"data", "msg"}`` with HTTP 200, errors included (:mod:`polynav.protocols.puwei.errors`). A body
that is not JSON is refused before the handler runs, but only after the token: an
unauthenticated caller learns nothing about its request. Handlers marked ``inline`` run on the
event loop, others on a worker thread. This module holds the one broad ``except`` per request:
log with ``exc_info``, answer code 1, keep serving (STYLE R4).
"""

from __future__ import annotations

import asyncio
import importlib
import json
import logging
from collections.abc import Iterable
from typing import Any

from starlette.applications import Starlette
from starlette.datastructures import UploadFile
from starlette.requests import Request
from starlette.responses import JSONResponse, Response
from starlette.routing import BaseRoute, Route, WebSocketRoute
from starlette.websockets import WebSocket

from polynav.errors import InvalidRequest
from polynav.protocols.puwei import errors
from polynav.protocols.puwei.context import Context
from polynav.protocols.puwei.endpoint import Endpoint, starlette_path
from polynav.protocols.puwei.request import PuweiRequest, UploadedFile, parse_body

log = logging.getLogger(__name__)
wire = logging.getLogger("polynav.protocols.puwei.wire")

#: The largest request body accepted [bytes] (map uploads are the biggest).
MAX_BODY_BYTES = 64 * 1024 * 1024
#: The WebSocket's path (A1: not in the source; docs/puwei.md).
WS_PATH = "/api/ws"
#: The header carrying the token, both ways (puwei-api §2.2, §4.1).
AUTH_HEADER = "authorization"


class PuweiJSON(JSONResponse):
    """JSON as the robot writes it: UTF-8, no NaN (a NaN would not parse in most clients)."""

    def render(self, content: Any) -> bytes:
        return json.dumps(content, ensure_ascii=False, allow_nan=False,
                          separators=(",", ":")).encode("utf-8")


def envelope(data: Any = None, *, code: int = errors.OK, msg: str = "") -> PuweiJSON:
    """The documented reply ``{"code", "data", "msg"}`` (puwei-api §2.1)."""
    return PuweiJSON({"code": code, "data": data, "msg": msg})


def error_reply(exc: BaseException) -> PuweiJSON:
    return envelope(None, code=errors.code_for(exc), msg=errors.message(exc))


async def read_request(request: Request) -> PuweiRequest:
    """The request's parts (:class:`PuweiRequest`).

    Raises:
        InvalidRequest: the body is too large or not JSON.
    """
    path = {k: str(v) for k, v in request.path_params.items()}
    query = dict(request.query_params.items())
    content_type = request.headers.get("content-type", "").split(";")[0].strip().lower()
    if content_type in ("multipart/form-data", "application/x-www-form-urlencoded"):
        form: dict[str, str] = {}
        files: dict[str, UploadedFile] = {}
        parsed = await request.form(max_files=8, max_fields=64)
        try:
            for key, value in parsed.multi_items():
                if isinstance(value, UploadFile):
                    files[key] = UploadedFile(value.filename or key, await value.read())
                else:
                    form[key] = value
        finally:
            await parsed.close()
        return PuweiRequest(path, query, form=form, files=files)
    raw = await request.body()
    if len(raw) > MAX_BODY_BYTES:
        raise InvalidRequest("body", f"larger than {MAX_BODY_BYTES} bytes")
    body, has_body = parse_body(raw)
    return PuweiRequest(path, query, body, has_body)


async def answer(ctx: Context, endpoint: Endpoint, request: Request) -> Response:
    """Check the token, parse, run the handler, wrap the reply or the error."""
    try:
        if not endpoint.public and not ctx.tokens.valid(request.headers.get(AUTH_HEADER)):
            raise errors.Unauthorized()
        parts = await read_request(request)
        if endpoint.inline:
            data = endpoint.handler(ctx, parts)
        else:
            data = await asyncio.to_thread(endpoint.handler, ctx, parts)
    except Exception as exc:  # the one broad except per request (STYLE R4)
        if errors.code_for(exc) == errors.INTERNAL:
            log.error("puwei: %s %s failed", request.method, endpoint.path, exc_info=True)
        else:
            log.debug("puwei: %s %s refused: %s", request.method, endpoint.path, exc)
        return error_reply(exc)
    if isinstance(data, Response):
        return data
    try:
        reply = envelope(data)
    except (TypeError, ValueError):
        log.error("puwei: %s %s: reply is not JSON", request.method, endpoint.path,
                  exc_info=True)
        return envelope(None, code=errors.INTERNAL, msg="internal error")
    wire.debug("out %s %s %s", request.method, request.url.path, reply.body[:200])
    return reply


async def websocket(ctx: Context, socket_: WebSocket) -> None:
    """``/api/ws?token=``: handed to the WebSocket side (``ws.py``), imported on first use so
    that the HTTP side serves before, and without, it; missing, the socket is closed 1011."""
    try:
        module = importlib.import_module("polynav.protocols.puwei.ws")
        websocket_session = module.websocket_session
    except (ImportError, AttributeError):
        log.error("puwei: WebSocket side is not available (polynav.protocols.puwei.ws)",
                  exc_info=True)
        # Accepted first: a close before the handshake is an HTTP 403, not the 1011 (server
        # error) a client can tell from a refused token.
        await socket_.accept()
        await socket_.close(code=1011)
        return
    await websocket_session(socket_, ctx)


def create_app(ctx: Context, endpoints: Iterable[Endpoint]) -> Starlette:
    """An ASGI app serving ``endpoints`` and the WebSocket with ``ctx``."""
    by_path: dict[str, dict[str, Endpoint]] = {}
    for endpoint in endpoints:
        by_path.setdefault(starlette_path(endpoint.path), {})[endpoint.method] = endpoint

    def make(methods: dict[str, Endpoint]) -> Any:
        async def handle(request: Request) -> Response:
            endpoint = methods.get(request.method)
            if endpoint is None:
                return envelope(None, code=errors.BAD_REQUEST,
                                msg=f"method {request.method} not allowed; use "
                                    + ", ".join(sorted(methods)))
            return await answer(ctx, endpoint, request)

        return handle

    async def ws_route(socket_: WebSocket) -> None:
        await websocket(ctx, socket_)

    routes: list[BaseRoute] = [
        Route(path, make(methods), methods=["GET", "POST", "PUT", "DELETE"])
        for path, methods in by_path.items()
    ]
    routes.append(WebSocketRoute(WS_PATH, ws_route))
    app = Starlette(routes=routes)

    async def not_found(request: Request, exc: Exception) -> Response:
        return envelope(None, code=errors.NOT_FOUND, msg=f"unknown endpoint {request.url.path}")

    app.add_exception_handler(404, not_found)
    return app
