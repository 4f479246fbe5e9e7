"""Password hashes (argon2id through argon2-cffi) and login tokens (random, stored hashed).

Nothing here is home-made cryptography: passwords go through argon2-cffi's ``PasswordHasher``
(argon2id, RFC 9106's low-memory parameters by default), tokens come from :mod:`secrets`, and a
token is stored as its SHA-256: a token carries 256 random bits, so unlike a password it cannot
be guessed from its hash and needs no slow hash.
"""

from __future__ import annotations

import functools
import hashlib
import logging
import secrets

from argon2 import PasswordHasher
from argon2.exceptions import InvalidHashError, VerificationError, VerifyMismatchError

log = logging.getLogger(__name__)

#: The hasher of new passwords. Verification reads the parameters from the stored hash, so a
#: hash made with other parameters (an older polynav, a test's cheaper ones) still verifies.
HASHER = PasswordHasher()

#: Longest password accepted [characters]: long enough for any passphrase, short enough that a
#: request cannot make the server hash megabytes.
MAX_PASSWORD = 1024


def hash_password(password: str, hasher: PasswordHasher = HASHER) -> str:
    """The argon2id string to store for ``password`` (salted: never twice the same).

    Raises:
        ValueError: an empty password or one longer than :data:`MAX_PASSWORD`.
    """
    if not password:
        raise ValueError("the password must not be empty")
    if len(password) > MAX_PASSWORD:
        raise ValueError(f"the password must be at most {MAX_PASSWORD} characters")
    return hasher.hash(password)


@functools.cache
def _decoy_hash() -> str:
    return HASHER.hash(secrets.token_urlsafe(16))


def verify_password(stored: str | None, password: str) -> bool:
    """Whether ``password`` matches the stored hash.

    ``stored`` is ``None`` for an unknown user: a decoy hash is verified instead, so the answer
    takes as long as for a known user and the timing does not tell which names exist.
    """
    try:
        matched = HASHER.verify(stored if stored is not None else _decoy_hash(), password)
    except (VerifyMismatchError, VerificationError, InvalidHashError):
        return False
    return bool(matched) and stored is not None


def new_token() -> str:
    """A fresh login token: 32 random bytes, URL-safe text (43 characters)."""
    return secrets.token_urlsafe(32)


def token_hash(token: str) -> str:
    """What the store keeps of a token: its SHA-256, hexadecimal."""
    return hashlib.sha256(token.encode("utf-8")).hexdigest()
