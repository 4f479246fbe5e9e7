"""Reply shapes the system endpoints share (galileo-http-a A-16, A-39).

The document gives most system endpoints one string field (``status`` or ``result``) "whether
it succeeded" and no failure form. polynav answers success with ``"ok"``, and a refusal with
the HTTP status of the error (:mod:`~polynav.protocols.galileo.errors`) and a body that keeps
the documented field, holding the reason, beside the generic error fields, so a client that
reads the documented field gets the reason and one that checks the HTTP status sees the error.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from starlette.responses import Response

from polynav.errors import PolynavError
from polynav.protocols.galileo import errors
from polynav.protocols.galileo.http import GalileoJSON

OK = "ok"


def refused(field: str, exc: PolynavError) -> Response:
    """``{<field>: reason, "status": "error", "description": reason}`` with the error's
    HTTP status (``status`` itself is the field when ``field`` is ``"status"``)."""
    reason = errors.description(exc)
    body: dict[str, Any] = {"status": "error", "description": reason}
    body[field] = reason
    return GalileoJSON(body, status_code=errors.http_status_for(exc))


def string_reply(field: str, action: Callable[[], object]) -> dict[str, Any] | Response:
    """Run ``action``: ``{field: "ok"}``, or :func:`refused` on a polynav error."""
    try:
        action()
    except PolynavError as exc:
        return refused(field, exc)
    return {field: OK}
