"""polynav exceptions to Puwei envelope codes, looked up along the MRO (STYLE R4).

The vendor documents only "0: success, non-0: failure" with ``msg`` as the message; its "system
error codes" page is missing from the export (puwei-api §2.1, A8). polynav's table
(docs/puwei.md, "Envelope codes"): every error is HTTP 200 with ``{"code": <n>, "data": null,
"msg": "<reason>"}``, since Puwei clients test ``code``, not the HTTP status.
"""

from __future__ import annotations

from polynav.errors import Conflict, InvalidRequest, NotFound, PolynavError, StorageError

#: Success.
OK = 0
#: An unexpected failure (logged with its traceback; the message says no more).
INTERNAL = 1
#: A malformed request: a bad parameter, a value out of range, a body that is not JSON.
BAD_REQUEST = 2
#: A name that does not exist (map, task, parameter, marker).
NOT_FOUND = 3
#: Valid, but not in the robot's current state (not navigating, already mapping ...).
REFUSED = 4
#: The site store failed.
STORAGE = 5
#: No ``authorization`` header, or a token the login did not give out (or expired).
UNAUTHORIZED = 401
#: Wrong user name or password at login.
LOGIN_FAILED = 402


class Unauthorized(PolynavError):
    """A protected endpoint called without a valid token."""

    def __init__(self) -> None:
        super().__init__("unauthorized: log in (POST /api/user/login) and send the token in "
                         "the authorization header")


class LoginFailed(PolynavError):
    """Wrong credentials."""

    def __init__(self) -> None:
        super().__init__("wrong username or password")


CODE_BY_EXCEPTION: dict[type[BaseException], int] = {
    Unauthorized: UNAUTHORIZED,
    LoginFailed: LOGIN_FAILED,
    InvalidRequest: BAD_REQUEST,
    NotFound: NOT_FOUND,
    Conflict: REFUSED,
    StorageError: STORAGE,
    PolynavError: INTERNAL,
}


def code_for(exc: BaseException) -> int:
    """The envelope code for ``exc``: the first class of its MRO in the table, else 1."""
    for cls in type(exc).__mro__:
        code = CODE_BY_EXCEPTION.get(cls)
        if code is not None:
            return code
    return INTERNAL


def message(exc: BaseException) -> str:
    """The ``msg``; an unexpected exception's text is not shown (it is logged)."""
    if isinstance(exc, NotFound):
        return f"{exc.kind} {exc.name!r} not found"
    if isinstance(exc, PolynavError):
        return str(exc) or type(exc).__name__
    return "internal error"
