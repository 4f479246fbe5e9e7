"""Each behaviour test runs on both backends: a SQLite file, and an empty database on a real
PostgreSQL server (tests/helpers/postgres.py)."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from polynav.fleet.records import FleetRecords, RecordsConfig
from tests.helpers.postgres import (  # noqa: F401
    postgres_database,
    postgres_server,
    postgres_url,
)

QUICK = RecordsConfig(connect_wait=5.0, retry_for=5.0)


@pytest.fixture(params=["sqlite", "postgresql"])
def records_url(request: pytest.FixtureRequest, tmp_path: Path) -> str:
    if request.param == "sqlite":
        return f"sqlite:///{tmp_path / 'fleet.db'}"
    url: str = request.getfixturevalue("postgres_url")
    return url


@pytest.fixture
def records(records_url: str) -> Iterator[FleetRecords]:
    with FleetRecords.open(records_url, name="fm-test", config=QUICK) as opened:
        yield opened
