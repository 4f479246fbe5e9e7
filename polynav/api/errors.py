"""polynav exceptions to HTTP answers: one table, looked up along the exception's MRO.

Every error body is ``{"error": {"code": str, "message": str}}``. Bad input is always a 4xx:
malformed JSON is 400, a body of the wrong shape or type 422, an unknown name 404, a command in
the wrong state 409. Only a real fault of ours is a 500, logged with its traceback.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from typing import Any

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from starlette.exceptions import HTTPException as StarletteHTTPException

from polynav.errors import (
    ConfigError,
    Conflict,
    InvalidRequest,
    NotFound,
    PolynavError,
    StorageError,
)

log = logging.getLogger(__name__)

ERROR_TABLE: dict[type[BaseException], tuple[int, str]] = {
    NotFound: (404, "not_found"),
    Conflict: (409, "conflict"),
    InvalidRequest: (422, "invalid_request"),
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


def error_body(code: str, message: str) -> dict[str, dict[str, str]]:
    """The one error shape of the native API."""
    return {"error": {"code": code, "message": message}}


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


async def _http_error(request: Request, exc: Exception) -> JSONResponse:
    assert isinstance(exc, StarletteHTTPException)
    code = _HTTP_CODES.get(exc.status_code, "http_error")
    return JSONResponse(
        error_body(code, str(exc.detail)),
        status_code=exc.status_code,
        headers=getattr(exc, "headers", None),
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
