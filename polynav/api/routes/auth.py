"""Log in and out of the native API, and who am I: served only when the API asks for a login.

``POST /api/login`` is the one route open without a token; the others go through the gate
(:mod:`polynav.api.auth_gate`) like every route. docs/auth.md shows their use.
"""

from __future__ import annotations

import logging
import math
from typing import Annotated, Literal

from fastapi import APIRouter, HTTPException, Request, Response
from fastapi.responses import JSONResponse
from pydantic import BaseModel, Field

from polynav.api.auth import (
    SESSION_COOKIE,
    LoginDenied,
    LoginService,
    LoginThrottled,
    presented_token,
)
from polynav.api.auth_passwords import MAX_PASSWORD
from polynav.api.deps import StoreDep
from polynav.api.errors import BODY, ErrorOut, Responses, error_body, responses
from polynav.api.schemas import Name
from polynav.store.user_tables import UserRecord

log = logging.getLogger(__name__)

router = APIRouter(prefix="/api", tags=["login"])

Role = Literal["viewer", "operator"]


class LoginIn(BaseModel):
    """A name and its password."""

    model_config = {"extra": "forbid"}

    name: Name
    password: Annotated[str, Field(min_length=1, max_length=MAX_PASSWORD)]


class UserOut(BaseModel):
    """Who a token belongs to."""

    name: str
    role: Role = Field(description="`viewer` reads; `operator` also drives and edits")


class LoginOut(UserOut):
    """A new token: send it as ``Authorization: Bearer <token>`` (the console's cookie carries
    the same one)."""

    token: str
    token_type: Literal["bearer"] = "bearer"
    expires_in: float = Field(description="seconds the token stays valid [s]")


_REFUSED: Responses = {
    401: {"model": ErrorOut, "description": "wrong name or password (code `unauthorized`)"},
    429: {"model": ErrorOut, "description": "too many failed logins in a row for this name "
          "or address: wait `Retry-After` seconds (code `too_many_attempts`)"},
}


def _user_out(user: UserRecord) -> UserOut:
    return UserOut(name=user.name, role="operator" if user.role == "operator" else "viewer")


@router.post("/login", operation_id="login", response_model=LoginOut,
             responses=responses(BODY, _REFUSED))
def login(body: LoginIn, request: Request, store: StoreDep) -> Response:
    """Trade a name and password for a token, also set as the session cookie (HttpOnly,
    SameSite=Strict). After five failures in a row for a name or an address, each further
    attempt waits twice as long as the previous one (429 with ``Retry-After`` until then)."""
    service: LoginService = request.app.state.login
    client = request.client.host if request.client is not None else "unknown"
    try:
        granted = service.login(store, body.name, body.password, client)
    except LoginThrottled as exc:
        return JSONResponse(error_body("too_many_attempts", str(exc)), status_code=429,
                            headers={"Retry-After": str(math.ceil(exc.wait))})
    except LoginDenied as exc:
        raise HTTPException(401, str(exc), headers={"WWW-Authenticate": "Bearer"}) from None
    out = LoginOut(**_user_out(granted.user).model_dump(), token=granted.token,
                   expires_in=granted.expires_in)
    answer = JSONResponse(out.model_dump())
    answer.set_cookie(SESSION_COOKIE, granted.token, max_age=int(granted.expires_in),
                      path="/api", httponly=True, samesite="strict")
    return answer


@router.post("/logout", operation_id="logout", status_code=204)
def logout(request: Request, store: StoreDep) -> Response:
    """Revoke the token this request presents and clear the session cookie."""
    service: LoginService = request.app.state.login
    service.logout(store, presented_token(request))
    answer = Response(status_code=204)
    answer.delete_cookie(SESSION_COOKIE, path="/api", httponly=True, samesite="strict")
    return answer


@router.get("/me", operation_id="get_me", response_model=UserOut)
def get_me(request: Request) -> UserOut:
    """The user of the token this request presents."""
    user: UserRecord = request.state.user
    return _user_out(user)
