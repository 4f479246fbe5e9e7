"""polynav exceptions to Galileo error replies, looked up along the MRO (STYLE R4).

The vendor's document defines no error body and no HTTP status (galileo-http-a A-39,
galileo-http-b A-29). polynav follows the companion specs' recommendation:

* an endpoint whose documented reply has ``result: bool`` answers HTTP 200
  ``{"result": false, "description": "<reason>"}`` (a Galileo script tests ``result``);
* every other endpoint answers HTTP 4xx/5xx ``{"status": "error", "description": "<reason>"}``;
* a missing or wrong token is HTTP 401 ``{"status": "error", "description": "invalid token"}``
  on every endpoint (galileo-http-a §1.4), whatever its reply shape.
"""

from __future__ import annotations

import logging
from typing import Any

from polynav.errors import Conflict, InvalidRequest, NotFound, PolynavError, StorageError

log = logging.getLogger(__name__)


class TokenRefused(PolynavError):
    """A request without a valid token while token checking is on."""

    def __init__(self) -> None:
        super().__init__("invalid token")


HTTP_STATUS_BY_EXCEPTION: dict[type[BaseException], int] = {
    TokenRefused: 401,
    InvalidRequest: 400,
    NotFound: 404,
    Conflict: 409,
    StorageError: 500,
    PolynavError: 500,
}


def http_status_for(exc: BaseException) -> int:
    """The HTTP status for ``exc``: the first class of its MRO in the table, else 500."""
    for cls in type(exc).__mro__:
        status = HTTP_STATUS_BY_EXCEPTION.get(cls)
        if status is not None:
            return status
    return 500


def description(exc: BaseException) -> str:
    """The ``description`` text; an unexpected exception's text is not shown (it is logged)."""
    if isinstance(exc, PolynavError):
        return str(exc)
    return "internal error"


def error_body(exc: BaseException, *, result_errors: bool) -> tuple[int, dict[str, Any]]:
    """The (HTTP status, body) answering a request that raised ``exc``."""
    status = http_status_for(exc)
    if result_errors and status != 401:
        return 200, {"result": False, "description": description(exc)}
    return status, {"status": "error", "description": description(exc)}
