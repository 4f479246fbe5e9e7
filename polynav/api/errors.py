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

from fastapi import FastAPI

from polynav import http_errors
from polynav.errors import (
    ConfigError,
    Conflict,
    InvalidRequest,
    NotFound,
    NotLocalized,
    PolynavError,
    StorageError,
)
from polynav.http_errors import ErrorOut, Responses, error_body
from polynav.runtime.settings import BeyondProfile

__all__ = ["BODY", "ERROR_TABLE", "FAULT", "LOOKUP", "STATE", "ErrorOut", "Responses",
           "error_body", "install_error_handlers", "responses", "status_and_code"]

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

_errors = http_errors.error_responses


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
    return http_errors.status_and_code(ERROR_TABLE, exc)


def install_error_handlers(app: FastAPI) -> None:
    """Make every error leave the app as the one JSON error shape."""
    http_errors.install_error_handlers(app, ERROR_TABLE)
