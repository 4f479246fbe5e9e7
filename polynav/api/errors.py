"""polynav exceptions to HTTP answers: one table, looked up along the exception's MRO.

Every error body is ``{"error": {"code": str, "message": str}}`` (:class:`ErrorOut`). Bad input is
always a 4xx: malformed JSON is 400, a request the OpenAPI document does not allow 422 (the
schemas carry every rule, so a request the document allows is never a 422), an unknown name 404,
and a well-formed request that the robot's state or the site refuses 409: the wrong mode, a name
taken, a pose in a wall, settings that contradict the current ones. Only a real fault of ours is
a 500, logged with its traceback.

The document says which of these each operation can answer: routes take their ``responses=``
from the tables below, one per kind of route (:data:`BODY`, :data:`LOOKUP`, :data:`STATE`), and
every operation can answer :data:`FAULT`. A 405 names the path's methods in ``Allow``.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from typing import Any

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from pydantic import BaseModel
from starlette.exceptions import HTTPException as StarletteHTTPException
from starlette.routing import Match

from polynav.errors import (
    ConfigError,
    Conflict,
    InvalidRequest,
    NotFound,
    NotLocalized,
    PolynavError,
    StorageError,
)
from polynav.runtime.settings import BeyondProfile

log = logging.getLogger(__name__)

ERROR_TABLE: dict[type[BaseException], tuple[int, str]] = {
    # A value the schema allows that the robot's profile forbids: the state of the robot refuses
    # it (another profile takes it), so a conflict, not a malformed request.
    BeyondProfile: (409, "beyond_profile"),
    NotFound: (404, "not_found"),
    NotLocalized: (409, "not_localized"),
    Conflict: (409, "conflict"),
    # Raised by the runtime or the store once the schema let the request in: refused, not malformed.
    InvalidRequest: (409, "invalid_request"),
    ConfigError: (422, "invalid_setting"),
    StorageError: (500, "storage_error"),
    PolynavError: (400, "bad_request"),
}

_HTTP_CODES = {
    400: "bad_request",
    401: "unauthorized",
    403: "forbidden",
    404: "not_found",
    405: "method_not_allowed",
    409: "conflict",
    415: "unsupported_media_type",
    422: "validation_error",
}


class ErrorDetail(BaseModel):
    code: str
    message: str


class ErrorOut(BaseModel):
    """The one error shape of the native API."""

    error: ErrorDetail


def error_body(code: str, message: str) -> dict[str, dict[str, str]]:
    """The one error shape of the native API."""
    return {"error": {"code": code, "message": message}}


Responses = dict[int | str, dict[str, Any]]


def _errors(described: dict[int, str]) -> Responses:
    return {status: {"model": ErrorOut, "description": text} for status, text in described.items()}


# A JSON body: it may not parse (400) or not match its schema (422).
BODY = _errors({
    400: "the body cannot be parsed (codes `malformed_json`, `bad_request`)",
    422: "the request does not match this document (code `validation_error`)",
})
# A named thing in the path or query: unknown (404), or a name the schema refuses (422).
LOOKUP = _errors({
    404: "no such map or point (code `not_found`)",
    422: "the request does not match this document (code `validation_error`)",
})
# A runtime command: refused in the robot's current state (409).
STATE = _errors({
    409: "refused in the robot's current state (codes `conflict`, `invalid_request`, "
         "`not_localized`, `beyond_profile`)",
})
# Any operation: a fault of the server (the disk, a bug), logged; never caused by the input.
FAULT = _errors({500: "a fault of the server (codes `internal`, `storage_error`)"})


def responses(*tables: Responses) -> Responses:
    """The union of some tables, for a route's ``responses=``."""
    merged: Responses = {}
    for table in tables:
        merged.update(table)
    return merged


def status_and_code(exc: BaseException) -> tuple[int, str]:
    """HTTP status and error code of a polynav exception (first match along its MRO)."""
    for cls in type(exc).__mro__:
        if cls in ERROR_TABLE:
            return ERROR_TABLE[cls]
    return 500, "internal"


def validation_message(errors: Sequence[Any]) -> str:
    """A one-line summary of pydantic errors: ``body.x: Input should be a valid number; ...``."""
    parts = []
    for err in errors:
        loc = ".".join(str(p) for p in err.get("loc", ()))
        parts.append(f"{loc}: {err.get('msg', 'invalid')}" if loc else str(err.get("msg")))
    return "; ".join(parts) or "invalid request"


async def _polynav_error(request: Request, exc: Exception) -> JSONResponse:
    status, code = status_and_code(exc)
    if status >= 500:
        log.error("%s %s failed: %s", request.method, request.url.path, exc, exc_info=exc)
    else:
        log.info("%s %s -> %d %s: %s", request.method, request.url.path, status, code, exc)
    return JSONResponse(error_body(code, str(exc)), status_code=status)


async def _validation_error(request: Request, exc: Exception) -> JSONResponse:
    assert isinstance(exc, RequestValidationError)
    errors = exc.errors()
    if any(err.get("type") == "json_invalid" for err in errors):
        return JSONResponse(
            error_body("malformed_json", validation_message(errors)), status_code=400
        )
    return JSONResponse(error_body("validation_error", validation_message(errors)), status_code=422)


_METHODS = ("DELETE", "GET", "HEAD", "OPTIONS", "PATCH", "POST", "PUT")


def allowed_methods(request: Request) -> list[str]:
    """Every method some route of the app serves at this request's path, sorted.

    Starlette's own 405 names only the methods of the first route that matched the path, but
    ``/api/points/{name}`` is served by three routes (GET, PUT, DELETE). Each method is tried
    against the routes as the router itself would, so included routers count too.
    """
    routes = request.app.router.routes
    return [
        method
        for method in _METHODS
        if any(route.matches({**request.scope, "method": method})[0] is Match.FULL
               for route in routes)
    ]


async def _http_error(request: Request, exc: Exception) -> JSONResponse:
    assert isinstance(exc, StarletteHTTPException)
    code = _HTTP_CODES.get(exc.status_code, "http_error")
    headers = dict(exc.headers or {})
    if exc.status_code == 405:
        headers["Allow"] = ", ".join(allowed_methods(request))
    return JSONResponse(
        error_body(code, str(exc.detail)), status_code=exc.status_code, headers=headers or None
    )


async def _internal_error(request: Request, exc: Exception) -> JSONResponse:
    log.error("%s %s failed", request.method, request.url.path, exc_info=exc)
    return JSONResponse(error_body("internal", "internal server error"), status_code=500)


def install_error_handlers(app: FastAPI) -> None:
    """Make every error leave the app as the one JSON error shape."""
    app.add_exception_handler(PolynavError, _polynav_error)
    app.add_exception_handler(RequestValidationError, _validation_error)
    app.add_exception_handler(StarletteHTTPException, _http_error)
    app.add_exception_handler(Exception, _internal_error)
