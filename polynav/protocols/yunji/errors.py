"""polynav exceptions to Yunji ``(status, error_message)``, looked up along the MRO (STYLE R4).

The spec (§2.2, §A-T6) has ``INVALID_REQUEST`` for bad parameters and unknown names,
``REQUEST_DENIED`` for a refusal in the robot's current state, ``UNKNOWN_ERROR`` for anything
else. Unknown points are markers to a Yunji client: their message is the spec's own
``Marker Not Found`` (§3.5.3).
"""

from __future__ import annotations

import logging

from polynav.errors import Conflict, InvalidRequest, NotFound, PolynavError
from polynav.protocols.yunji.messages import Status

log = logging.getLogger(__name__)

STATUS_BY_EXCEPTION: dict[type[BaseException], Status] = {
    InvalidRequest: Status.INVALID_REQUEST,
    NotFound: Status.INVALID_REQUEST,
    Conflict: Status.REQUEST_DENIED,
    PolynavError: Status.UNKNOWN_ERROR,
}

MARKER_NOT_FOUND = "Marker Not Found"


def status_for(exc: BaseException) -> tuple[Status, str]:
    """The Yunji status and message for ``exc``: the first class of its MRO in the table."""
    for cls in type(exc).__mro__:
        status = STATUS_BY_EXCEPTION.get(cls)
        if status is not None:
            return status, _message(exc)
    return Status.UNKNOWN_ERROR, "internal error"


def _message(exc: BaseException) -> str:
    if isinstance(exc, NotFound) and exc.kind == "point":
        return MARKER_NOT_FOUND
    return str(exc)
