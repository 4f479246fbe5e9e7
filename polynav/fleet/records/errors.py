"""Failures of the fleet's records: a database that cannot be reached or used."""

from __future__ import annotations

from sqlalchemy.engine import make_url
from sqlalchemy.exc import ArgumentError

from polynav.errors import StorageError


class FleetRecordsError(StorageError):
    """The fleet's records database cannot be reached, or answers with an error that retrying
    does not cure. The message names the database by :func:`redacted` URL, never with its
    password (it ends up in logs and in answers to operators)."""


def redacted(url: str) -> str:
    """``url`` with its password replaced by ``***``, for messages and logs."""
    try:
        return make_url(url).render_as_string(hide_password=True)
    except ArgumentError:
        # Not a URL SQLAlchemy can parse: keep only the scheme, the rest may hold a secret.
        scheme, sep, _ = url.partition("://")
        return f"{scheme}://..." if sep else "<unparsable database URL>"
