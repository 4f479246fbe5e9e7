"""Reaching the records' database: a clear error, quickly, when it cannot be reached at start;
retries with backoff when the connection is lost while running; the password never shown."""

from __future__ import annotations

import logging
import os
import pwd
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import psycopg
import pytest
from sqlalchemy import create_engine, insert
from sqlalchemy.exc import IntegrityError

from polynav.fleet.records import FleetRecords, FleetRecordsError, RecordsConfig, redacted
from polynav.fleet.records import schema as s
from tests.helpers.postgres import PostgresServer, _free_port, running_postgres

SHORT = RecordsConfig(connect_wait=0.5, retry_for=0.5, backoff_initial=0.05)


def test_an_unreachable_postgresql_is_a_clear_error_after_the_bounded_wait() -> None:
    port = _free_port()  # nothing listens there
    url = f"postgresql://fleet:s3cret-pw@127.0.0.1:{port}/fleet"
    started = time.monotonic()
    with pytest.raises(FleetRecordsError) as caught:
        FleetRecords.open(url, config=SHORT)
    waited = time.monotonic() - started
    message = str(caught.value)
    assert f"postgresql://fleet:***@127.0.0.1:{port}/fleet" in message
    assert "unreachable after 0.5 s" in message or "unreachable after 0.6 s" in message
    assert "s3cret-pw" not in message
    assert 0.5 <= waited < 8.0


def test_a_refusing_server_fails_at_once_without_waiting(postgres_server: PostgresServer) -> None:
    url = postgres_server.url("no_such_database", password="s3cret-pw")
    started = time.monotonic()
    with pytest.raises(FleetRecordsError) as caught:
        FleetRecords.open(url, config=RecordsConfig(connect_wait=30.0))
    assert time.monotonic() - started < 10.0  # not the 30 s: waiting cannot cure it
    assert "no_such_database" in str(caught.value)
    assert "s3cret-pw" not in str(caught.value)


@pytest.mark.parametrize("url", ["mysql://u:pw@127.0.0.1/x", "not a url",
                                 "postgresql+asyncpg://u:pw@127.0.0.1/x"])
def test_an_unsupported_url_is_refused_without_its_password(url: str) -> None:
    with pytest.raises(FleetRecordsError) as caught:
        FleetRecords.open(url, config=SHORT)
    assert ":pw@" not in str(caught.value)


def test_a_sqlite_file_that_cannot_be_made_is_a_clear_error(tmp_path: Path) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("not a directory")
    with pytest.raises(FleetRecordsError) as caught:
        FleetRecords.open(f"sqlite:///{blocker}/fleet.db", config=SHORT)
    assert str(blocker) in str(caught.value)


def test_redacted_hides_the_password_only() -> None:
    assert redacted("postgresql://u:pw@h:5432/db") == "postgresql://u:***@h:5432/db"
    assert redacted("sqlite:////var/lib/fleet.db") == "sqlite:////var/lib/fleet.db"


@pytest.fixture
def own_server() -> Iterator[PostgresServer]:
    """A server of this test's own, to stop and start."""
    with running_postgres() as server:
        yield server


class _LostHandler(logging.Handler):
    """Sets ``lost`` when the records log that their connection was lost."""

    def __init__(self) -> None:
        super().__init__(logging.WARNING)
        self.lost = threading.Event()

    def emit(self, record: logging.LogRecord) -> None:
        if "lost" in record.getMessage():
            self.lost.set()


def test_an_operation_retries_until_the_server_is_back(own_server: PostgresServer) -> None:
    records = FleetRecords.open(own_server.url(), config=RecordsConfig(retry_for=20.0))
    handler = _LostHandler()
    logger = logging.getLogger("polynav.fleet.records.database")
    logger.addHandler(handler)
    try:
        assert records.grant_lease("lift:A", "r1", now=0.0, duration=60.0) is not None
        port = own_server.port
        own_server.stop()

        def restart_once_lost() -> None:
            if handler.lost.wait(timeout=20.0):
                own_server.start(port)

        restarter = threading.Thread(target=restart_once_lost)
        restarter.start()
        mission = records.add_mission([{"point": "lab"}], now=1.0, mission_id="m1")
        restarter.join(timeout=30.0)
        assert handler.lost.is_set()
        assert mission.mission_id == "m1"
        assert records.grant_lease("lift:A", "r2", now=2.0, duration=5.0) is None
        assert [e.what for e in records.audit()] == ["lease.granted", "mission.added"]
    finally:
        logger.removeHandler(handler)
        records.close()


def test_a_connection_lost_for_good_is_a_clear_error_after_retry_for(
        own_server: PostgresServer) -> None:
    url = own_server.url(password="s3cret-pw")
    records = FleetRecords.open(url, config=RecordsConfig(retry_for=1.0))
    try:
        records.add_mission([{"point": "lab"}], now=1.0)
        own_server.stop()
        started = time.monotonic()
        with pytest.raises(FleetRecordsError) as caught:
            records.missions()
        assert time.monotonic() - started < 8.0
        assert "unreachable" in str(caught.value)
        assert "s3cret-pw" not in str(caught.value)
    finally:
        records.close()


def test_the_database_refuses_a_second_lease_in_one_slot(postgres_url: str,
                                                         tmp_path: Path) -> None:
    """The guarantee under the transactions: even a writer that skips every check cannot put
    two leases on a capacity-1 resource."""
    for url in (postgres_url, f"sqlite:///{tmp_path / 'fleet.db'}"):
        FleetRecords.open(url).close()
        engine = create_engine(url.replace("postgresql://", "postgresql+psycopg://"))
        row = {"resource": "lift:A", "slot": 0, "capacity": 1, "granted_at": 0.0,
               "expires_at": 10.0}
        try:
            with engine.begin() as conn:
                conn.execute(insert(s.leases).values(holder="r1", **row))
            with pytest.raises(IntegrityError), engine.begin() as conn:
                conn.execute(insert(s.leases).values(holder="r2", **row))
            with pytest.raises(IntegrityError), engine.begin() as conn:
                conn.execute(insert(s.leases).values(holder="r2", **{**row, "slot": 1}))
        finally:
            engine.dispose()


def test_the_test_server_runs_as_an_unprivileged_user(postgres_server: PostgresServer) -> None:
    """PostgreSQL refuses to run as root; the helper starts it as another user when we are."""
    with psycopg.connect(postgres_server.url()) as conn:
        row = conn.execute("SELECT current_setting('data_directory')").fetchone()
    assert row is not None and row[0] == str(postgres_server.data)
    status = Path(f"/proc/{postgres_server.pid}/status").read_text()
    uid = int(next(line for line in status.splitlines() if line.startswith("Uid:")).split()[1])
    assert uid != 0
    assert uid == (os.geteuid() if os.geteuid() != 0 else pwd.getpwnam("postgres").pw_uid)
