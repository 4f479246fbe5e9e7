"""Opening the fleet's records database, and running transactions on it that survive races and
a lost connection.

Two backends through one SQLAlchemy Core engine:

- **SQLite** (``sqlite:///path``): every transaction starts with ``BEGIN IMMEDIATE``, so it holds
  the database's write lock from its first read: two processes on one file take turns, and a
  check-then-write (is the lift free? then grant it) cannot interleave. WAL journal, and a busy
  timeout so a process waits for the lock instead of failing.
- **PostgreSQL** (``postgresql://...``, driven by psycopg 3): a transaction asks for the
  isolation it needs: SERIALIZABLE for leases (PostgreSQL aborts one of two transactions whose
  reads and writes cross, with a serialization failure), READ COMMITTED for the mission queue
  (claims use ``FOR UPDATE SKIP LOCKED``, made for that level).

A transaction is a function of the connection, so it can be run again from the start:

- after a *race* (serialization failure, deadlock, a unique constraint hit by a concurrent
  writer), at once with a short random pause, at most :attr:`RecordsConfig.race_attempts`
  times;
- after a *lost connection* (the server restarted, the network dropped), or a SQLite file
  still locked by another process past the busy timeout, with exponential backoff for at most
  :attr:`RecordsConfig.retry_for`; past that, :class:`FleetRecordsError`.

A transaction whose COMMIT was lost may have committed; run again, it must find its own work
done, so every operation of the store is written to be idempotent (it checks before it writes).

This is I/O: its waits are real time (``time.monotonic``, ``time.sleep``), never the site clock.
"""

from __future__ import annotations

import contextlib
import enum
import logging
import random
import sqlite3
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeVar

from sqlalchemy import Connection, Engine, create_engine, event, inspect
from sqlalchemy.engine import URL, make_url
from sqlalchemy.exc import ArgumentError, DBAPIError, OperationalError
from sqlalchemy.pool import StaticPool

from polynav.errors import ConfigError
from polynav.fleet.records.errors import FleetRecordsError, redacted
from polynav.fleet.records.schema import metadata

log = logging.getLogger(__name__)

_KEY = "fleet.records."

T = TypeVar("T")


@dataclass(frozen=True, slots=True)
class RecordsConfig:
    """How long the records wait for their database, in seconds of wall time.

    Attributes:
        connect_wait: at start, keep trying to reach the database this long before
            :class:`FleetRecordsError` (a fleet started with its database still booting waits
            for it; one pointed at a wrong address says so soon).
        retry_for: while running, retry an operation whose connection was lost this long.
        backoff_initial: the first pause after a lost connection; doubled each retry.
        backoff_max: the longest pause between retries.
        race_attempts: how many times a transaction that lost a race is run again.
        sqlite_busy: how long SQLite waits for another process's write lock.
    """

    connect_wait: float = 10.0
    retry_for: float = 30.0
    backoff_initial: float = 0.05
    backoff_max: float = 1.0
    race_attempts: int = 200
    sqlite_busy: float = 30.0

    def __post_init__(self) -> None:
        for name in ("connect_wait", "retry_for", "backoff_initial", "backoff_max",
                     "sqlite_busy"):
            value = getattr(self, name)
            if not value > 0.0:
                raise ConfigError(_KEY + name, f"must be > 0, got {value}")
        if self.race_attempts < 1:
            raise ConfigError(_KEY + "race_attempts", f"must be >= 1, got {self.race_attempts}")


class Isolation(enum.Enum):
    """What a transaction needs from the database (SQLite gives both with BEGIN IMMEDIATE)."""

    SERIALIZABLE = "SERIALIZABLE"
    READ_COMMITTED = "READ COMMITTED"


class _Failure(enum.Enum):
    RACE = "race"
    LOST = "lost"


# PostgreSQL SQLSTATEs: serialization failure, deadlock, unique violation (a concurrent insert).
_RACE_STATES = frozenset({"40001", "40P01", "23505"})
# Admin or crash shutdown, cannot connect now (starting up or shutting down).
_LOST_STATES = frozenset({"57P01", "57P02", "57P03"})
# Wrong password or role, no such database: waiting does not cure these.
_FATAL_STATE_CLASSES = ("28", "3D")


class RecordsDatabase:
    """The engine and the retrying transaction runner (see the module docstring)."""

    def __init__(self, engine: Engine, url: str, config: RecordsConfig) -> None:
        """Use :meth:`open`."""
        self.engine = engine
        self.url = url
        self.config = config
        self.is_postgres = engine.dialect.name == "postgresql"
        # An in-memory SQLite database is one connection: threads take turns on it.
        self._one_at_a_time = (threading.Lock() if isinstance(engine.pool, StaticPool)
                               else contextlib.nullcontext())

    @classmethod
    def open(cls, url: str, config: RecordsConfig | None = None,
             application_name: str = "polynav-fleet") -> RecordsDatabase:
        """Connect to ``url`` and create the tables that are missing.

        Raises:
            FleetRecordsError: an unsupported URL, or the database not reached (or refusing us)
                within ``config.connect_wait``.
        """
        config = config or RecordsConfig()
        engine = _engine(url, config, application_name)
        db = cls(engine, url, config)
        started = time.monotonic()
        pause = config.backoff_initial
        while True:
            try:
                metadata.create_all(engine)
                if set(inspect(engine).get_table_names()) >= set(metadata.tables):
                    return db
            except DBAPIError as exc:
                waited = time.monotonic() - started
                if _fatal(exc) or waited >= config.connect_wait:
                    engine.dispose()
                    raise FleetRecordsError(
                        f"fleet records database {redacted(url)} unreachable after "
                        f"{waited:.1f} s: {_reason(exc)}") from exc
                # Not up yet, or another fleet manager creating the same tables right now.
                log.info("fleet records database %s not ready (%s); retrying",
                         redacted(url), _reason(exc))
            time.sleep(min(pause, max(0.0, started + config.connect_wait - time.monotonic())))
            pause = min(pause * 2.0, config.backoff_max)

    def close(self) -> None:
        self.engine.dispose()

    def run(self, work: Callable[[Connection], T], isolation: Isolation) -> T:
        """Run ``work`` in one transaction and commit it; run it again after a race or a lost
        connection (module docstring). ``work`` must be safe to run more than once.

        Raises:
            FleetRecordsError: the connection stayed lost for ``retry_for``, races went on for
                ``race_attempts``, or the database failed otherwise.
        """
        races = 0
        lost_since: float | None = None
        pause = self.config.backoff_initial
        while True:
            try:
                return self._once(work, isolation)
            except DBAPIError as exc:
                failure = _classify(exc, self.is_postgres)
                if failure is _Failure.RACE:
                    races += 1
                    if races >= self.config.race_attempts:
                        raise FleetRecordsError(
                            f"fleet records on {redacted(self.url)}: still conflicting after "
                            f"{races} attempts: {_reason(exc)}") from exc
                    time.sleep(random.uniform(0.0, 0.002 * min(races, 10)))
                    continue
                if failure is None:
                    raise FleetRecordsError(
                        f"fleet records on {redacted(self.url)} failed: {_reason(exc)}") from exc
                now = time.monotonic()
                if lost_since is None:
                    lost_since = now
                    log.warning("fleet records database %s lost or busy (%s); retrying for "
                                "%g s",
                                redacted(self.url), _reason(exc), self.config.retry_for)
                if now - lost_since >= self.config.retry_for:
                    raise FleetRecordsError(
                        f"fleet records database {redacted(self.url)} unreachable for "
                        f"{now - lost_since:.1f} s: {_reason(exc)}") from exc
                time.sleep(min(pause, lost_since + self.config.retry_for - now))
                pause = min(pause * 2.0, self.config.backoff_max)

    def _once(self, work: Callable[[Connection], T], isolation: Isolation) -> T:
        with self._one_at_a_time, self.engine.connect() as conn:
            if self.is_postgres:
                conn = conn.execution_options(isolation_level=isolation.value)
            with conn.begin():
                return work(conn)


def _engine(url: str, config: RecordsConfig, application_name: str) -> Engine:
    try:
        parsed = make_url(url)
    except ArgumentError as exc:
        raise FleetRecordsError(f"not a database URL: {redacted(url)}") from exc
    backend = parsed.get_backend_name()
    if backend == "postgresql":
        return _postgres_engine(parsed, config, application_name)
    if backend == "sqlite" and parsed.get_driver_name() in ("pysqlite", ""):
        return _sqlite_engine(parsed, config)
    raise FleetRecordsError(f"unsupported fleet records database {redacted(url)}: use "
                            "sqlite:///path or postgresql://user@host:port/name")


def _postgres_engine(url: URL, config: RecordsConfig, application_name: str) -> Engine:
    if url.get_driver_name() not in ("psycopg", "psycopg2", ""):
        raise FleetRecordsError(f"unsupported PostgreSQL driver in "
                                f"{url.render_as_string(hide_password=True)}: "
                                "use postgresql:// (psycopg 3)")
    return create_engine(
        url.set(drivername="postgresql+psycopg"),
        pool_pre_ping=True,  # a pooled connection to a restarted server is replaced, not used
        connect_args={"connect_timeout": max(1, round(config.connect_wait)),
                      "application_name": application_name},
    )


def _sqlite_engine(url: URL, config: RecordsConfig) -> Engine:
    memory = url.database in (None, "", ":memory:")
    if not memory and url.database is not None:
        try:
            Path(url.database).parent.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise FleetRecordsError(f"fleet records database {redacted(url.render_as_string())}"
                                    f" cannot be made: {exc}") from exc
    engine = create_engine(
        url.set(drivername="sqlite+pysqlite"),
        connect_args={"timeout": config.sqlite_busy, "check_same_thread": False},
        # One in-memory database is one connection; every checkout must get that one.
        **({"poolclass": StaticPool} if memory else {}),
    )

    @event.listens_for(engine, "connect")
    def _on_connect(dbapi_conn: Any, _record: Any) -> None:
        # The driver's own transaction handling begins lazily (after reads); take it over so
        # every transaction begins with BEGIN IMMEDIATE (below).
        dbapi_conn.isolation_level = None
        cursor = dbapi_conn.cursor()
        if not memory:
            cursor.execute("PRAGMA journal_mode=WAL")
        cursor.execute(f"PRAGMA busy_timeout = {int(config.sqlite_busy * 1000)}")
        cursor.close()

    @event.listens_for(engine, "begin")
    def _on_begin(conn: Connection) -> None:
        conn.exec_driver_sql("BEGIN IMMEDIATE")

    return engine


def _classify(exc: DBAPIError, is_postgres: bool) -> _Failure | None:
    """Whether ``exc`` is a lost race, a lost connection, or neither (a real failure)."""
    if exc.connection_invalidated:
        return _Failure.LOST
    orig = exc.orig
    if is_postgres:
        state = getattr(orig, "sqlstate", None)
        if state in _RACE_STATES:
            return _Failure.RACE
        if state in _LOST_STATES or (state or "").startswith("08"):
            return _Failure.LOST
        if isinstance(exc, OperationalError) and state is None:
            return _Failure.LOST  # no answer from the server at all (refused, reset)
        return None
    # SQLite: BEGIN IMMEDIATE lets no other writer in, so a constraint failure is no race;
    # a lock still held past the busy timeout is another process's long transaction: wait.
    if isinstance(orig, sqlite3.OperationalError) and any(
            word in str(orig) for word in ("locked", "busy")):
        return _Failure.LOST
    return None


# A server that is up but not yet (or no longer) serving answers FATAL too: wait for it.
_PASSING_FATALS = ("starting up", "shutting down", "in recovery", "too many")


def _fatal(exc: DBAPIError) -> bool:
    """Whether the server answered and refused us for good (no such database or role, a
    wrong password), so waiting longer cannot help."""
    state = getattr(exc.orig, "sqlstate", None) or ""
    if state.startswith(_FATAL_STATE_CLASSES):
        return True
    # At connection start libpq reports no SQLSTATE, only the server's FATAL message.
    text = str(exc.orig)
    return "FATAL:" in text and not any(words in text for words in _PASSING_FATALS)


def _reason(exc: DBAPIError) -> str:
    """The driver's own message, first line (SQLAlchemy's wrapper adds the SQL and a link)."""
    text = str(exc.orig).strip() if exc.orig is not None else str(exc)
    return text.splitlines()[0] if text else type(exc.orig).__name__
