"""What only SQLite needs: another process's write lock waited for, an in-memory database
shared by threads."""

from __future__ import annotations

import logging
import sqlite3
import threading
from pathlib import Path

import pytest

from polynav.fleet.records import FleetRecords, FleetRecordsError, RecordsConfig


class _BusyHandler(logging.Handler):
    def __init__(self) -> None:
        super().__init__(logging.WARNING)
        self.busy = threading.Event()

    def emit(self, record: logging.LogRecord) -> None:
        if "busy" in record.getMessage():
            self.busy.set()


def test_a_write_lock_held_past_the_busy_timeout_is_waited_for(tmp_path: Path) -> None:
    path = tmp_path / "fleet.db"
    config = RecordsConfig(sqlite_busy=0.1, retry_for=20.0)
    with FleetRecords.open(f"sqlite:///{path}", config=config) as records:
        other = sqlite3.connect(path, isolation_level=None, check_same_thread=False)
        other.execute("BEGIN IMMEDIATE")  # another fleet manager in a long transaction
        handler = _BusyHandler()
        logger = logging.getLogger("polynav.fleet.records.database")
        logger.addHandler(handler)

        def commit_once_waited_for() -> None:
            handler.busy.wait(timeout=20.0)
            other.execute("COMMIT")

        releaser = threading.Thread(target=commit_once_waited_for)
        releaser.start()
        try:
            lease = records.grant_lease("lift:A", "r1", now=0.0, duration=5.0)
        finally:
            releaser.join(timeout=30.0)
            logger.removeHandler(handler)
            other.close()
        assert handler.busy.is_set()
        assert lease is not None and lease.holder == "r1"


def test_a_write_lock_never_given_back_is_a_clear_error(tmp_path: Path) -> None:
    path = tmp_path / "fleet.db"
    config = RecordsConfig(sqlite_busy=0.1, retry_for=0.3)
    with FleetRecords.open(f"sqlite:///{path}", config=config) as records:
        other = sqlite3.connect(path, isolation_level=None, check_same_thread=False)
        other.execute("BEGIN IMMEDIATE")
        try:
            with pytest.raises(FleetRecordsError) as caught:
                records.grant_lease("lift:A", "r1", now=0.0, duration=5.0)
        finally:
            other.close()
    assert "locked" in str(caught.value)


def test_an_in_memory_database_is_shared_by_threads() -> None:
    with FleetRecords.open("sqlite://") as records:
        barrier = threading.Barrier(3)
        winners: dict[int, list[str]] = {k: [] for k in range(20)}

        def ask(robot: str) -> None:
            for k in range(20):
                barrier.wait(timeout=20.0)
                if records.grant_lease("lift:A", robot, now=k * 10.0, duration=5.0):
                    winners[k].append(robot)

        threads = [threading.Thread(target=ask, args=(f"r{i}",)) for i in range(3)]
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join(timeout=30.0)
        assert [len(w) for w in winners.values()] == [1] * 20
        grants = [e.detail["holder"] for e in records.audit() if e.what == "lease.granted"]
        assert grants == [w[0] for w in winners.values()]
