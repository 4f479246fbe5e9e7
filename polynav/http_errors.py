"""The one JSON error shape of polynav's HTTP APIs, and the handlers that give it.

Both the robot's native API (:mod:`polynav.api.errors`) and the fleet manager's
(:mod:`polynav.fleet_api.errors`) answer every error as ``{"error": {"code": str, "message":
str}}``; they differ only in which exceptions map to which status and code (each passes its own
table to :func:`install_error_handlers`). The handlers live here, below both, so neither API
imports the other. Malformed JSON is a 400, a request the document does not allow a 422, an
HTTP error its own status (a 405 naming the path's methods in ``Allow``), anything unexpected a
500 logged with its traceback.
"""

from __future__ import annotations

import logging
from collections.abc import Mapping, Sequence
from typing import Any

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from pydantic import BaseModel
from starlette.exceptions import HTTPException as StarletteHTTPException
from starlette.routing import Match

from polynav.errors import PolynavError

log = logging.getLogger(__name__)

ErrorTable = Mapping[type[BaseException], tuple[int, str]]
"""An API's polynav exceptions to (HTTP status, error code), looked up along the MRO."""

Responses = dict[int | str, dict[str, Any]]

HTTP_CODES = {
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
    """The one error shape of polynav's HTTP APIs."""

    error: ErrorDetail


def error_body(code: str, message: str) -> dict[str, dict[str, str]]:
    """The one error shape, as a JSON body."""
    return {"error": {"code": code, "message": message}}


def error_responses(described: Mapping[int, str]) -> Responses:
    """A route's ``responses=``: each status with the error shape and what it means."""
    return {status: {"model": ErrorOut, "description": text} for status, text in described.items()}


def status_and_code(table: ErrorTable, exc: BaseException) -> tuple[int, str]:
    """HTTP status and error code of ``exc`` in ``table`` (first match along its MRO; else a
    500 ``internal``)."""
    for cls in type(exc).__mro__:
        if cls in table:
            return table[cls]
    return 500, "internal"


def validation_message(errors: Sequence[Any]) -> str:
    """A one-line summary of pydantic errors: ``body.x: Input should be a valid number; ...``."""
    parts = []
    for err in errors:
        loc = ".".join(str(p) for p in err.get("loc", ()))
        parts.append(f"{loc}: {err.get('msg', 'invalid')}" if loc else str(err.get("msg")))
    return "; ".join(parts) or "invalid request"


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


async def _validation_error(request: Request, exc: Exception) -> JSONResponse:
    assert isinstance(exc, RequestValidationError)
    errors = exc.errors()
    if any(err.get("type") == "json_invalid" for err in errors):
        return JSONResponse(
            error_body("malformed_json", validation_message(errors)), status_code=400
        )
    return JSONResponse(error_body("validation_error", validation_message(errors)), status_code=422)


async def _http_error(request: Request, exc: Exception) -> JSONResponse:
    assert isinstance(exc, StarletteHTTPException)
    code = HTTP_CODES.get(exc.status_code, "http_error")
    headers = dict(exc.headers or {})
    if exc.status_code == 405:
        headers["Allow"] = ", ".join(allowed_methods(request))
    return JSONResponse(
        error_body(code, str(exc.detail)), status_code=exc.status_code, headers=headers or None
    )


async def _internal_error(request: Request, exc: Exception) -> JSONResponse:
    log.error("%s %s failed", request.method, request.url.path, exc_info=exc)
    return JSONResponse(error_body("internal", "internal server error"), status_code=500)


def install_error_handlers(app: FastAPI, table: ErrorTable) -> None:
    """Make every error leave ``app`` as the one JSON error shape, polynav's exceptions by
    ``table``."""

    async def polynav_error(request: Request, exc: Exception) -> JSONResponse:
        status, code = status_and_code(table, exc)
        if status >= 500:
            log.error("%s %s failed: %s", request.method, request.url.path, exc, exc_info=exc)
        else:
            log.info("%s %s -> %d %s: %s", request.method, request.url.path, status, code, exc)
        return JSONResponse(error_body(code, str(exc)), status_code=status)

    app.add_exception_handler(PolynavError, polynav_error)
    app.add_exception_handler(RequestValidationError, _validation_error)
    app.add_exception_handler(StarletteHTTPException, _http_error)
    app.add_exception_handler(Exception, _internal_error)
