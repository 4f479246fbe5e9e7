"""Each behaviour test runs on both backends: a SQLite file, and a fresh database on a real
PostgreSQL server (tests/helpers/postgres.py)."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from polynav.fleet.records import FleetRecords, RecordsConfig
from tests.helpers.postgres import PostgresServer, postgres_server  # noqa: F401

QUICK = RecordsConfig(connect_wait=5.0, retry_for=5.0)


@pytest.fixture(params=["sqlite", "postgresql"])
def records_url(request: pytest.FixtureRequest, tmp_path: Path) -> Iterator[str]:
    if request.param == "sqlite":
        yield f"sqlite:///{tmp_path / 'fleet.db'}"
        return
    server: PostgresServer = request.getfixturevalue("postgres_server")
    name = server.create_database()
    yield server.url(name)
    server.drop_database(name)


@pytest.fixture
def records(records_url: str) -> Iterator[FleetRecords]:
    with FleetRecords.open(records_url, name="fm-test", config=QUICK) as opened:
        yield opened
