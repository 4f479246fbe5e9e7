"""The Galileo HTTP transport (port 3546): parse parameters, check the token, dispatch, answer.

One Starlette route per path; the method picks the endpoint. Parameters come from the query
string, a JSON body and multipart form fields (:mod:`polynav.protocols.galileo.params`). A body
that is not JSON, or a JSON body that is not an object, is a 400 before any handler runs. Handlers
marked ``inline`` run on the event loop (snapshot reads, cheap enough to poll in a tight loop),
others on a worker thread. This module holds the one broad ``except`` per request: log with
``exc_info``, answer the generic error, keep serving (STYLE R4).
"""

from __future__ import annotations

import asyncio
import json
import logging
from collections.abc import Mapping
from typing import Any

from starlette.applications import Starlette
from starlette.datastructures import UploadFile
from starlette.requests import Request
from starlette.responses import JSONResponse, Response
from starlette.routing import Route

from polynav.errors import InvalidRequest
from polynav.protocols.galileo import errors
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.endpoint import Endpoint
from polynav.protocols.galileo.params import Params, UploadedFile

log = logging.getLogger(__name__)
wire = logging.getLogger("polynav.protocols.galileo.wire")

#: The largest request body accepted [bytes] (map archives are the biggest).
MAX_BODY_BYTES = 64 * 1024 * 1024


class GalileoJSON(JSONResponse):
    """JSON as the robot writes it: UTF-8, no NaN (a NaN would not parse in most clients)."""

    def render(self, content: Any) -> bytes:
        return json.dumps(content, ensure_ascii=False, allow_nan=False,
                          separators=(",", ":")).encode("utf-8")


def _error(exc: BaseException, endpoint: Endpoint | None) -> Response:
    status, body = errors.error_body(exc, result_errors=endpoint is not None
                                     and endpoint.result_errors)
    return GalileoJSON(body, status_code=status)


async def read_params(request: Request) -> Params:
    """The request's parameters: the query string overlaid by a JSON body or form fields.

    Raises:
        InvalidRequest: the body is not JSON, or too large.
    """
    values: dict[str, Any] = dict(request.query_params.items())
    values.update(request.path_params)  # ``/system/saved_images/{file_timestamp}``
    content_type = request.headers.get("content-type", "").split(";")[0].strip().lower()
    files: dict[str, UploadedFile] = {}
    body: Any = None
    if content_type in ("multipart/form-data", "application/x-www-form-urlencoded"):
        form = await request.form(max_files=16, max_fields=256)
        try:
            for name, value in form.multi_items():
                if isinstance(value, UploadFile):
                    data = await value.read()
                    files[name] = UploadedFile(
                        value.filename or name, data,
                        value.content_type or "application/octet-stream",
                    )
                else:
                    values[name] = value
        finally:
            await form.close()
        return Params(values, files)
    raw = await request.body()
    if len(raw) > MAX_BODY_BYTES:
        raise InvalidRequest("body", f"larger than {MAX_BODY_BYTES} bytes")
    if raw.strip():
        try:
            body = json.loads(raw)
        except (ValueError, UnicodeDecodeError) as exc:
            raise InvalidRequest("body", f"must be JSON: {exc}") from None
        if isinstance(body, dict):
            values.update(body)
    return Params(values, files, body)


def create_app(ctx: Context, table: Mapping[tuple[str, str], Endpoint]) -> Starlette:
    """An ASGI app serving ``table`` with ``ctx``."""
    by_path: dict[str, dict[str, Endpoint]] = {}
    for (method, path), endpoint in table.items():
        by_path.setdefault(path, {})[method] = endpoint

    def make(methods: dict[str, Endpoint]) -> Any:
        async def handle(request: Request) -> Response:
            endpoint = methods.get(request.method)
            if endpoint is None:
                return GalileoJSON(
                    {"status": "error",
                     "description": f"method {request.method} not allowed; use "
                                    + ", ".join(sorted(methods))},
                    status_code=405,
                )
            return await answer(ctx, endpoint, request)

        return handle

    routes = [
        Route(path, make(methods), methods=["GET", "POST", "PUT", "DELETE", "PATCH"])
        for path, methods in by_path.items()
    ]
    app = Starlette(routes=routes)

    async def not_found(request: Request, exc: Exception) -> Response:
        return GalileoJSON(
            {"status": "error", "description": f"unknown endpoint {request.url.path}"},
            status_code=404,
        )

    app.add_exception_handler(404, not_found)
    return app


async def answer(ctx: Context, endpoint: Endpoint, request: Request) -> Response:
    """Parse, check the token, run the handler, format the reply or the error."""
    try:
        try:
            params = await read_params(request)
        except InvalidRequest:
            # A body that does not parse cannot carry the token: without a valid one in the
            # query the request is refused as unauthenticated, not told what was wrong.
            if not endpoint.public and not ctx.tokens.accepts(request.query_params.get("token")):
                raise errors.TokenRefused() from None
            raise
        if not endpoint.public and not ctx.tokens.accepts(params.values.get("token")):
            raise errors.TokenRefused()
        if endpoint.inline:
            reply = endpoint.handler(ctx, params)
        else:
            reply = await asyncio.to_thread(endpoint.handler, ctx, params)
    except Exception as exc:  # the one broad except per request (STYLE R4)
        if errors.http_status_for(exc) >= 500:
            log.error("galileo: %s %s failed", request.method, endpoint.path, exc_info=True)
        else:
            log.debug("galileo: %s %s refused: %s", request.method, endpoint.path, exc)
        return _error(exc, endpoint)
    if isinstance(reply, Response):
        return reply
    try:
        return GalileoJSON(reply)
    except (TypeError, ValueError):
        log.error("galileo: %s %s: reply is not JSON", request.method, endpoint.path,
                  exc_info=True)
        return GalileoJSON({"status": "error", "description": "internal error"}, status_code=500)
