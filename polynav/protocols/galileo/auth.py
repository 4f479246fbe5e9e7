"""Galileo token auth: the vendor's ``config.json`` and the tokens handed out by ``/token``.

Spec galileo-http-a §1.3–1.4 and E-01. Checking is on only when ``no_token_check`` is ``false``
(A-03), or when polynav's ``require_token`` forces it. A token is 32 lower-case hex digits, valid
until the server restarts or the credentials change. ``/token`` and ``/api/v1/token`` are always
served without one. The token may come in the query string, a JSON body or a form field.
Tokens and passwords are never logged (STYLE R9).
"""

from __future__ import annotations

import hmac
import json
import logging
import re
import secrets
import threading
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from polynav.errors import ConfigError
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.endpoint import Reply, RouteList
from polynav.protocols.galileo.params import Params

log = logging.getLogger(__name__)

ROUTES = RouteList()

_TRAILING_COMMA = re.compile(r",(\s*[}\]])")


@dataclass(frozen=True, slots=True)
class ServiceSettings:
    """The keys of the vendor's ``config.json`` (galileo-http-a §1.3), with its defaults."""

    username: str = "admin"
    password: str = "admin"
    allow_update: bool = True
    no_token_check: bool = True
    auto_charge: bool = False

    def to_dict(self) -> dict[str, Any]:
        return {
            "username": self.username,
            "password": self.password,
            "allow_update": self.allow_update,
            "no_token_check": self.no_token_check,
            "auto_charge": self.auto_charge,
        }


def load_settings(path: Path) -> ServiceSettings:
    """Read ``config.json``; defaults when the file does not exist.

    The vendor's own default file ends its object with a trailing comma (not JSON); such a file
    is accepted as the robot accepts it.

    Raises:
        ConfigError: the file is unreadable, not a JSON object, or a key has the wrong type.
    """
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        return ServiceSettings()
    except OSError as exc:
        raise ConfigError("galileo.config_file", f"cannot read {path}: {exc}") from None
    try:
        data = json.loads(_TRAILING_COMMA.sub(r"\1", text))
    except ValueError as exc:
        raise ConfigError("galileo.config_file", f"{path} is not JSON: {exc}") from None
    if not isinstance(data, dict):
        raise ConfigError("galileo.config_file", f"{path} must hold a JSON object")
    defaults = ServiceSettings()
    values: dict[str, Any] = {}
    for key, default in defaults.to_dict().items():
        value = data.get(key, default)
        if type(value) is not type(default):
            raise ConfigError(
                f"galileo.config_file.{key}",
                f"must be {type(default).__name__}, got {type(value).__name__}",
            )
        values[key] = value
    return ServiceSettings(**values)


class TokenBook:
    """The credentials and the tokens issued with them."""

    def __init__(self, settings: ServiceSettings, *, require_token: bool = False) -> None:
        self._settings = settings
        self._require = require_token
        self._tokens: set[str] = set()
        self._lock = threading.Lock()

    @property
    def checking(self) -> bool:
        """Whether requests need a token."""
        return self._require or not self._settings.no_token_check

    @property
    def settings(self) -> ServiceSettings:
        return self._settings

    def replace_settings(self, settings: ServiceSettings) -> None:
        """New credentials invalidate every token handed out with the old ones."""
        with self._lock:
            if (settings.username, settings.password) != (
                self._settings.username, self._settings.password
            ):
                self._tokens.clear()
            self._settings = settings

    def issue(self, username: str, password: str) -> str | None:
        """A new token for the right credentials, else ``None``."""
        ok_user = hmac.compare_digest(username.encode(), self._settings.username.encode())
        ok_pass = hmac.compare_digest(password.encode(), self._settings.password.encode())
        if not (ok_user and ok_pass):
            log.info("galileo: token refused: wrong credentials")
            return None
        token = secrets.token_hex(16)
        with self._lock:
            self._tokens.add(token)
        return token

    def accepts(self, token: object) -> bool:
        """Whether a request carrying ``token`` (``None``: none) may proceed."""
        if not self.checking:
            return True
        if not isinstance(token, str) or not token:
            return False
        with self._lock:
            return token in self._tokens


@ROUTES.get("/token", public=True, inline=True, prefix="")
@ROUTES.get("/token", public=True, inline=True)
def get_token(ctx: Context, params: Params) -> Reply:
    """E-01: ``{"result": bool, "token": str}``; wrong credentials give ``result: false`` and an
    empty token."""
    token = ctx.tokens.issue(params.text("username"), params.text("password"))
    if token is None:
        return {"result": False, "token": "", "description": "wrong username or password"}
    return {"result": True, "token": token}
