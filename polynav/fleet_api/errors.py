"""Fleet errors to HTTP answers, in the native API's one error shape
(``{"error": {"code": str, "message": str}}``, :mod:`polynav.api.errors`).

Bad input is a 4xx: malformed JSON 400, a body or a query the document does not allow 422 (a
stop that is not a point and a map is caught by the schema), an unknown mission, robot, map or
point 404, a request the records' state refuses (a mission id taken by other stops, a mission
already ended) 409. A records database that stays unreachable is a 503 (try again). Anything
else is a fault of ours: 500, logged with its traceback.
"""

from __future__ import annotations

from fastapi import FastAPI

from polynav import http_errors
from polynav.errors import Conflict, InvalidRequest, NotFound, PolynavError
from polynav.fleet.records import FleetRecordsError
from polynav.http_errors import ErrorOut, Responses, error_body

__all__ = ["ERROR_TABLE", "ErrorOut", "Responses", "error_body", "errors",
           "install_error_handlers"]

ERROR_TABLE: dict[type[BaseException], tuple[int, str]] = {
    NotFound: (404, "not_found"),
    Conflict: (409, "conflict"),
    InvalidRequest: (422, "invalid_request"),
    FleetRecordsError: (503, "records_unavailable"),
    PolynavError: (400, "bad_request"),
}

errors = http_errors.error_responses
"""A route's ``responses=``: each status with the error shape and what it means."""


def install_error_handlers(app: FastAPI) -> None:
    """Make every error leave the app as the one JSON error shape."""
    http_errors.install_error_handlers(app, ERROR_TABLE)
