"""One site's SQLite connection, its transactions and the cache of hot reads.

See :mod:`polynav.store.site_store` for why a write cannot tear and how the cache is kept.
"""

from __future__ import annotations

import contextlib
import logging
import sqlite3
import threading
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import Any

from polynav.errors import Conflict, NotFound, StorageError
from polynav.site import Point
from polynav.store.rows import (
    POINT_COLUMNS,
    point_from_row,
)

log = logging.getLogger(__name__)

MAPS_DIR = "maps"


class SiteDatabase:
    """The connection, its lock, the read cache and transactions: what every table shares.

    Not used alone: :class:`~polynav.store.site_store.SiteStore` is built from its tables.
    """

    def __init__(self, data_dir: Path, conn: sqlite3.Connection) -> None:
        """Use :meth:`open`; this only wraps an already migrated connection."""
        self._data_dir = data_dir
        self._maps_dir = data_dir / MAPS_DIR
        self._conn: sqlite3.Connection | None = conn
        self._lock = threading.RLock()
        self._cache: dict[tuple[Any, ...], Any] = {}
        self._data_version: int | None = None


    # ---------------------------------------------------------------- internals

    @contextlib.contextmanager
    def _read(self) -> Iterator[sqlite3.Connection]:
        """A read transaction: every query inside sees the same committed state."""
        with self._transaction("BEGIN") as conn:
            yield conn

    @contextlib.contextmanager
    def _write(self) -> Iterator[sqlite3.Connection]:
        """A write transaction holding the database's write lock from its start."""
        with self._transaction("BEGIN IMMEDIATE") as conn:
            yield conn

    def _cached(self, key: tuple[Any, ...], load: Callable[[], Any]) -> Any:
        """``load()``'s value, kept until this store writes or another connection commits.

        Values must be immutable (tuples of frozen records): every caller shares them.
        """
        with self._lock:
            conn = self._conn
            if conn is None:
                raise StorageError("the site store is closed")
            try:
                version = int(conn.execute("PRAGMA data_version").fetchone()[0])
            except sqlite3.Error as exc:
                raise StorageError(f"site database unavailable: {exc}") from exc
            if version != self._data_version:
                self._cache.clear()
                self._data_version = version
            if key not in self._cache:
                self._cache[key] = load()
            return self._cache[key]

    @contextlib.contextmanager
    def _transaction(self, begin: str) -> Iterator[sqlite3.Connection]:
        with self._lock:
            conn = self._conn
            if conn is None:
                raise StorageError("the site store is closed")
            try:
                conn.execute(begin)
            except sqlite3.Error as exc:
                raise StorageError(f"site database unavailable: {exc}") from exc
            if begin != "BEGIN":
                self._cache.clear()  # a write: whatever it changes, nothing cached survives it
            try:
                yield conn
                conn.execute("COMMIT")
            except BaseException as exc:
                with contextlib.suppress(sqlite3.Error):
                    conn.execute("ROLLBACK")
                if isinstance(exc, sqlite3.IntegrityError):
                    raise Conflict(f"site database constraint: {exc}") from exc
                if isinstance(exc, sqlite3.Error):
                    raise StorageError(f"site database failed: {exc}") from exc
                raise

    def _named(
        self, key: tuple[Any, ...], load: Callable[[], Any], kind: str, name: str
    ) -> Any:
        """The record called ``name`` among the cached records ``load`` reads (floors, maps).

        Raises:
            NotFound: none has that name.
        """
        for record in self._cached(key, load):
            if record.name == name:
                return record
        raise NotFound(kind, name)

    def _require_map(self, conn: sqlite3.Connection, name: str) -> None:
        if conn.execute("SELECT 1 FROM maps WHERE name = ?", (name,)).fetchone() is None:
            raise NotFound("map", name)

    def _map_rows(self, table: str, columns: str, map_name: str, order: str) -> list[Any]:
        """The rows of a per-map table (keepouts, routes) for one map, in ``order``.

        Raises:
            NotFound: no such map.
        """
        with self._read() as conn:
            self._require_map(conn, map_name)
            return conn.execute(
                f"SELECT {columns} FROM {table} WHERE map_name = ? ORDER BY {order}",
                (map_name,),
            ).fetchall()

    def _replace_map_rows(
        self, table: str, columns: str, map_name: str, rows: Sequence[tuple[Any, ...]]
    ) -> None:
        """Replace all rows of a per-map table for one map in one transaction; each row starts
        with ``map_name``, then the other ``columns``.

        Raises:
            NotFound: no such map.
        """
        marks = ", ".join("?" for _ in range(columns.count(",") + 2))
        with self._write() as conn:
            self._require_map(conn, map_name)
            conn.execute(f"DELETE FROM {table} WHERE map_name = ?", (map_name,))
            conn.executemany(
                f"INSERT INTO {table} (map_name, {columns}) VALUES ({marks})", rows
            )

    def _require_floor(self, conn: sqlite3.Connection, name: str) -> None:
        if conn.execute("SELECT 1 FROM floors WHERE name = ?", (name,)).fetchone() is None:
            raise NotFound("floor", name)

    def _point_in(self, conn: sqlite3.Connection, map_name: str, name: str) -> Point:
        self._require_map(conn, map_name)
        row = conn.execute(
            f"SELECT {POINT_COLUMNS} FROM points p WHERE p.map_name = ? AND p.name = ?",
            (map_name, name),
        ).fetchone()
        if row is None:
            raise NotFound("point", f"{map_name}/{name}")
        return point_from_row(row)
