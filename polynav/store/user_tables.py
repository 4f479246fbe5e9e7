"""The native API's users and their login tokens in the site store.

Only hashes are stored: a user's password as the argon2 string the API computed (the store never
sees a password), a token as the SHA-256 of the random token handed out (a token is 256 random
bits, so a fast hash is enough: there is nothing to guess). A token goes with its user (``ON
DELETE CASCADE``) and a new password revokes every token of the user, so ``polynav users rm``
and ``polynav users passwd`` take effect on a running server at its next request.

Times: ``created`` of a user is an ISO date-time for people; a token's ``created`` and
``expires`` are seconds since the epoch, given by the caller (the store reads no clock).
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from polynav.errors import Conflict, InvalidRequest, NotFound
from polynav.store.database import SiteDatabase
from polynav.store.rows import check_name

log = logging.getLogger(__name__)

#: ``viewer`` reads (GET and the WebSocket), ``operator`` also drives and edits.
ROLES = ("viewer", "operator")

_USER_COLUMNS = "name, role, created"


@dataclass(frozen=True, slots=True)
class UserRecord:
    """A user of the native API, without the password hash.

    Attributes:
        name: the login name, unique in the site.
        role: ``viewer`` or ``operator``.
        created: when the user was added (ISO date-time).
    """

    name: str
    role: str
    created: str


def _user(row: Sequence[Any]) -> UserRecord:
    return UserRecord(row[0], row[1], row[2])


def _check_role(role: str) -> None:
    if role not in ROLES:
        raise InvalidRequest("user.role", f"must be one of {', '.join(ROLES)}, got {role!r}")


def _check_hash(password_hash: str) -> None:
    # A guard against storing a password by mistake: only an argon2 or bcrypt string goes in.
    if not isinstance(password_hash, str) or not password_hash.startswith(("$argon2", "$2")):
        raise InvalidRequest("user.password_hash", "expected an argon2 or bcrypt hash string")


class UserTables(SiteDatabase):
    """Users (name, role, password hash) and their tokens (hash, expiry)."""

    # ---------------------------------------------------------------- users

    def users(self) -> list[UserRecord]:
        """Every user, by name."""
        with self._read() as conn:
            rows = conn.execute(f"SELECT {_USER_COLUMNS} FROM users ORDER BY name").fetchall()
        return [_user(r) for r in rows]

    def user(self, name: str) -> UserRecord:
        """Raises NotFound: no such user."""
        with self._read() as conn:
            row = conn.execute(
                f"SELECT {_USER_COLUMNS} FROM users WHERE name = ?", (name,)).fetchone()
        if row is None:
            raise NotFound("user", name)
        return _user(row)

    def user_count(self) -> int:
        """How many users there are (``polynav run`` off loopback needs one)."""
        with self._read() as conn:
            return int(conn.execute("SELECT COUNT(*) FROM users").fetchone()[0])

    def password_hash(self, name: str) -> str | None:
        """The stored hash of the user's password; ``None`` for an unknown user."""
        with self._read() as conn:
            row = conn.execute(
                "SELECT password_hash FROM users WHERE name = ?", (name,)).fetchone()
        return None if row is None else str(row[0])

    def add_user(self, name: str, role: str, password_hash: str, created: str) -> UserRecord:
        """Add a user.

        Raises:
            InvalidRequest: a bad name, an unknown role, or something not a password hash.
            Conflict: the name is taken.
        """
        check_name("user.name", name)
        _check_role(role)
        _check_hash(password_hash)
        with self._write() as conn:
            if conn.execute("SELECT 1 FROM users WHERE name = ?", (name,)).fetchone():
                raise Conflict(f"user {name!r} already exists")
            conn.execute(
                "INSERT INTO users (name, role, password_hash, created) VALUES (?, ?, ?, ?)",
                (name, role, password_hash, created),
            )
        log.info("added user %r (%s)", name, role)
        return UserRecord(name, role, created)

    def remove_user(self, name: str) -> None:
        """Remove a user and its tokens. Raises NotFound: no such user."""
        with self._write() as conn:
            if conn.execute("DELETE FROM users WHERE name = ?", (name,)).rowcount == 0:
                raise NotFound("user", name)
        log.info("removed user %r", name)

    def set_password(self, name: str, password_hash: str) -> None:
        """Replace a user's password hash and revoke every token of the user.

        Raises:
            InvalidRequest: something not a password hash.
            NotFound: no such user.
        """
        _check_hash(password_hash)
        with self._write() as conn:
            changed = conn.execute(
                "UPDATE users SET password_hash = ? WHERE name = ?", (password_hash, name)
            ).rowcount
            if changed == 0:
                raise NotFound("user", name)
            conn.execute("DELETE FROM tokens WHERE user_name = ?", (name,))
        log.info("changed the password of user %r (its tokens are revoked)", name)

    # ---------------------------------------------------------------- tokens

    def add_token(self, token_hash: str, name: str, created: float, expires: float) -> None:
        """Record a token (its hash) of a user until ``expires``; drops expired tokens.

        Raises:
            NotFound: no such user (removed meanwhile).
        """
        with self._write() as conn:
            if conn.execute("SELECT 1 FROM users WHERE name = ?", (name,)).fetchone() is None:
                raise NotFound("user", name)
            conn.execute("DELETE FROM tokens WHERE expires <= ?", (created,))
            conn.execute(
                "INSERT INTO tokens (token_hash, user_name, created, expires) VALUES (?, ?, ?, ?)",
                (token_hash, name, created, expires),
            )

    def token_user(self, token_hash: str, now: float) -> UserRecord | None:
        """The user a token belongs to, if the token exists and has not expired at ``now``."""
        with self._read() as conn:
            row = conn.execute(
                "SELECT u.name, u.role, u.created FROM tokens t JOIN users u "
                "ON u.name = t.user_name WHERE t.token_hash = ? AND t.expires > ?",
                (token_hash, now),
            ).fetchone()
        return None if row is None else _user(row)

    def remove_token(self, token_hash: str) -> bool:
        """Revoke a token; whether there was one."""
        with self._write() as conn:
            return conn.execute(
                "DELETE FROM tokens WHERE token_hash = ?", (token_hash,)).rowcount > 0
