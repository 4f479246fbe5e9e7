from __future__ import annotations

import sqlite3
from pathlib import Path

import pytest

from polynav.errors import StorageError
from polynav.geometry import Pose2D
from polynav.site import Point
from polynav.store import SiteStore
from polynav.store.schema import MIGRATIONS, SCHEMA_VERSION, Migration, migrate, schema_version
from tests.unit.store.grids import small_map

TABLES = ["automations", "connections", "floors", "keepouts", "maps", "meta", "points", "routes",
          "schedules", "settings", "tasks", "tokens", "users"]


def _connect(path: Path) -> sqlite3.Connection:
    return sqlite3.connect(str(path), isolation_level=None)


def _tables(conn: sqlite3.Connection) -> list[str]:
    rows = conn.execute("SELECT name FROM sqlite_master WHERE type = 'table' ORDER BY name")
    return [r[0] for r in rows if r[0] != "schema_version"]


def test_migrations_are_numbered_from_one() -> None:
    assert [m.version for m in MIGRATIONS] == list(range(1, len(MIGRATIONS) + 1))
    assert SCHEMA_VERSION == len(MIGRATIONS) == 4


def test_open_records_the_schema_version_and_creates_the_tables(tmp_path: Path) -> None:
    SiteStore.open(tmp_path / "data").close()
    conn = _connect(tmp_path / "data" / "site.db")
    try:
        assert schema_version(conn) == SCHEMA_VERSION
        assert _tables(conn) == TABLES
        assert conn.execute("PRAGMA journal_mode").fetchone()[0] == "wal"
        assert conn.execute("PRAGMA integrity_check").fetchone()[0] == "ok"
    finally:
        conn.close()


def test_migrate_an_empty_database_from_version_0(tmp_path: Path) -> None:
    conn = _connect(tmp_path / "site.db")
    try:
        assert schema_version(conn) == 0
        assert migrate(conn) == SCHEMA_VERSION
        assert schema_version(conn) == SCHEMA_VERSION
        assert _tables(conn) == TABLES
        assert migrate(conn) == SCHEMA_VERSION  # nothing left to do
    finally:
        conn.close()


def test_store_opens_a_database_left_at_version_0(tmp_path: Path) -> None:
    data = tmp_path / "data"
    data.mkdir()
    _connect(data / "site.db").close()  # an empty file, as after a crash before migration 1
    with SiteStore.open(data) as store:
        assert store.maps() == []


EXTRA = Migration(
    SCHEMA_VERSION + 1,
    "points get a note",
    (
        "ALTER TABLE points ADD COLUMN note TEXT NOT NULL DEFAULT ''",
        "UPDATE points SET note = 'from v1'",
    ),
)


def test_migration_2_keeps_version_1_points_without_a_custom_type(tmp_path: Path) -> None:
    conn = _connect(tmp_path / "site.db")
    try:
        assert migrate(conn, MIGRATIONS[:1]) == 1
        conn.execute("INSERT INTO maps VALUES ('lab', NULL, 0.05, 1, 1, 0, 0, 0, 'lab.yaml')")
        conn.execute("INSERT INTO points VALUES ('lab', 'p', 1.0, 2.0, 0.5, 'custom', 7)")
        assert migrate(conn, MIGRATIONS[:2]) == 2
        rows = conn.execute("SELECT name, kind, number, custom_type FROM points").fetchall()
        assert rows == [("p", "custom", 7, None)]
    finally:
        conn.close()


def test_migrate_from_the_current_version_keeps_the_data(tmp_path: Path) -> None:
    data = tmp_path / "data"
    with SiteStore.open(data) as store:
        store.save_map("lab", small_map(["."]))
        store.add_point(Point("p", "lab", Pose2D(1.0, 2.0, 0.5)))
    conn = _connect(data / "site.db")
    try:
        assert schema_version(conn) == SCHEMA_VERSION
        assert migrate(conn, (*MIGRATIONS, EXTRA)) == SCHEMA_VERSION + 1
        assert schema_version(conn) == SCHEMA_VERSION + 1
        rows = conn.execute("SELECT map_name, name, x, y, theta, note FROM points").fetchall()
        assert rows == [("lab", "p", 1.0, 2.0, 0.5, "from v1")]
    finally:
        conn.close()


def test_failed_migration_is_rolled_back_entirely(tmp_path: Path) -> None:
    broken = Migration(
        SCHEMA_VERSION + 1, "half a step", ("CREATE TABLE later (id INTEGER)", "NOT SQL")
    )
    conn = _connect(tmp_path / "site.db")
    try:
        migrate(conn)
        with pytest.raises(StorageError, match="schema migration failed"):
            migrate(conn, (*MIGRATIONS, broken))
        assert schema_version(conn) == SCHEMA_VERSION
        assert "later" not in _tables(conn)
    finally:
        conn.close()


def test_store_refuses_a_database_from_a_newer_polynav(tmp_path: Path) -> None:
    data = tmp_path / "data"
    SiteStore.open(data).close()
    conn = _connect(data / "site.db")
    try:
        migrate(conn, (*MIGRATIONS, EXTRA))
    finally:
        conn.close()
    newer = f"schema version {SCHEMA_VERSION + 1}, newer than this polynav knows"
    with pytest.raises(StorageError, match=newer):
        SiteStore.open(data)


def test_migrations_must_be_consecutive(tmp_path: Path) -> None:
    conn = _connect(tmp_path / "site.db")
    try:
        gap = SCHEMA_VERSION + 2
        with pytest.raises(StorageError, match=f"migration {gap - 1} is numbered {gap}"):
            migrate(conn, (*MIGRATIONS, Migration(gap, "gap", ())))
        assert schema_version(conn) == 0
    finally:
        conn.close()
