"""Fleet records on a real PostgreSQL server and SQLite files, used by several processes."""

from __future__ import annotations

from tests.helpers.postgres import (  # noqa: F401
    postgres_database,
    postgres_server,
    postgres_url,
)
