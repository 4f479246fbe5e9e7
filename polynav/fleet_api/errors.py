"""Fleet errors to HTTP answers, in the native API's one error shape
(``{"error": {"code": str, "message": str}}``, :mod:`polynav.api.errors`).

Bad input is a 4xx: malformed JSON 400, a body or a query the document does not allow 422 (a
stop that is not a point and a map is caught by the schema), an unknown mission, robot, map or
point 404, a request the records' state refuses (a mission id taken by other stops, a mission
already ended) 409. A records database that stays unreachable is a 503 (try again). Anything
else is a fault of ours: 500, logged with its traceback.
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

from polynav.errors import Conflict, InvalidRequest, NotFound, PolynavError
from polynav.fleet.records import FleetRecordsError

log = logging.getLogger(__name__)

ERROR_TABLE: dict[type[BaseException], tuple[int, str]] = {
    NotFound: (404, "not_found"),
    Conflict: (409, "conflict"),
    InvalidRequest: (422, "invalid_request"),
    FleetRecordsError: (503, "records_unavailable"),
    PolynavError: (400, "bad_request"),
}

_HTTP_CODES = {400: "bad_request", 404: "not_found", 405: "method_not_allowed",
               409: "conflict", 415: "unsupported_media_type", 422: "validation_error"}


class ErrorDetail(BaseModel):
    code: str
    message: str


class ErrorOut(BaseModel):
    """The one error shape."""

    error: ErrorDetail


Responses = dict[int | str, dict[str, Any]]


def errors(described: dict[int, str]) -> Responses:
    """A route's ``responses=``: each status with the error shape and what it means."""
    return {status: {"model": ErrorOut, "description": text}
            for status, text in described.items()}


def error_body(code: str, message: str) -> dict[str, dict[str, str]]:
    return {"error": {"code": code, "message": message}}


def status_and_code(exc: BaseException) -> tuple[int, str]:
    """HTTP status and error code of a polynav exception (first match along its MRO)."""
    for cls in type(exc).__mro__:
        if cls in ERROR_TABLE:
            return ERROR_TABLE[cls]
    return 500, "internal"


def _validation_message(problems: Sequence[Any]) -> str:
    parts = []
    for err in problems:
        loc = ".".join(str(p) for p in err.get("loc", ()))
        parts.append(f"{loc}: {err.get('msg', 'invalid')}" if loc else str(err.get("msg")))
    return "; ".join(parts) or "invalid request"


async def _polynav_error(request: Request, exc: Exception) -> JSONResponse:
    status, code = status_and_code(exc)
    if status >= 500:
        log.error("%s %s failed: %s", request.method, request.url.path, exc)
    else:
        log.info("%s %s -> %d %s: %s", request.method, request.url.path, status, code, exc)
    return JSONResponse(error_body(code, str(exc)), status_code=status)


async def _validation_error(request: Request, exc: Exception) -> JSONResponse:
    assert isinstance(exc, RequestValidationError)
    problems = exc.errors()
    if any(err.get("type") == "json_invalid" for err in problems):
        return JSONResponse(error_body("malformed_json", _validation_message(problems)),
                            status_code=400)
    return JSONResponse(error_body("validation_error", _validation_message(problems)),
                        status_code=422)


async def _http_error(request: Request, exc: Exception) -> JSONResponse:
    assert isinstance(exc, StarletteHTTPException)
    return JSONResponse(error_body(_HTTP_CODES.get(exc.status_code, "http_error"),
                                   str(exc.detail)),
                        status_code=exc.status_code, headers=dict(exc.headers or {}) or None)


async def _internal_error(request: Request, exc: Exception) -> JSONResponse:
    log.error("%s %s failed", request.method, request.url.path, exc_info=exc)
    return JSONResponse(error_body("internal", "internal server error"), status_code=500)


def install_error_handlers(app: FastAPI) -> None:
    """Make every error leave the app as the one JSON error shape."""
    app.add_exception_handler(PolynavError, _polynav_error)
    app.add_exception_handler(RequestValidationError, _validation_error)
    app.add_exception_handler(StarletteHTTPException, _http_error)
    app.add_exception_handler(Exception, _internal_error)
