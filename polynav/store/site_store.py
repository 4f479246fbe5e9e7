"""The site store: one robot's persistent site data in a data directory.

Layout of ``data_dir``::

    site.db            SQLite: floors, maps, points, keepouts, routes, connections, settings,
                       tasks, schedules, automation tasks, the native API's users and tokens
    site.db-wal, -shm  SQLite's write-ahead log (WAL mode)
    maps/<slug>-<n>.yaml + .png   one ROS map per map row, named by a serial that never repeats

Why it cannot tear (DESIGN §6):

* every method is one SQLite transaction (``BEGIN IMMEDIATE`` for writes, so two processes on
  the same directory queue instead of failing half-way);
* a map is written to *fresh* files (temp file, fsync, rename: :func:`ros_map.save_map`) while
  the write transaction is held, then the row pointing at them commits, and only then are the
  previous files removed. A crash leaves either the old row with its old files or the new row
  with its new files; leftover files that no row names are removed the next time the store
  opens (under the write lock, so never the files of another process's save in flight);
* ``synchronous=FULL``: every commit is fsynced to the WAL before the method returns. With
  ``NORMAL`` a power cut could undo a commit after the old map files were already deleted,
  leaving a row pointing at nothing; FULL costs one fsync per write, which a site store (a few
  writes a minute) does not notice.

Thread safety: one connection (``check_same_thread=False``) guarded by a lock, so the API may
call from any thread; each call holds the lock for its whole transaction.

Hot reads come from memory (docs/decisions.md, "Hot paths"): floors, map records, the points
of a map and point counts are cached after the first read, and the cache is dropped by every
write through this store and whenever SQLite's ``data_version`` shows a commit by another
connection (``polynav points add`` on the same directory while a server runs). Checking
``data_version`` reads only the WAL index in shared memory, never the database file.
"""

from __future__ import annotations

import logging
from collections.abc import Mapping, Sequence
from pathlib import Path
from types import TracebackType
from typing import TYPE_CHECKING, Any

from polynav.errors import InvalidRequest, StorageError
from polynav.store.records import ConnectionRecord, RouteRecord
from polynav.store.schema import migrate
from polynav.store.seed import SeedPlan, seed_plan

if TYPE_CHECKING:
    from polynav.worlds.world import World

from polynav.store.database import MAPS_DIR
from polynav.store.map_tables import MapTables
from polynav.store.point_tables import PointTables
from polynav.store.rows import (
    MAP_COLUMNS,
    check_name,
    connect,
    from_json,
    info_columns,
    point_columns,
    to_json,
)
from polynav.store.task_tables import TaskTables
from polynav.store.user_tables import UserTables

log = logging.getLogger(__name__)

DB_FILE = "site.db"
_SEEDED_KEY = "seeded_from"


class SiteStore(MapTables, PointTables, TaskTables, UserTables):
    """Floors, maps, points, keepouts, routes, connections, settings, tasks, schedules and
    automation tasks of one site.

    Build it with :meth:`open`. Every method either completes or changes nothing, and raises
    :class:`~polynav.errors.NotFound` (unknown map, floor, point),
    :class:`~polynav.errors.InvalidRequest` (a malformed value),
    :class:`~polynav.errors.Conflict` (a name already taken, an ambiguous name, a map in use)
    or :class:`~polynav.errors.StorageError` (the disk or database failed). Its tables live by
    subject in :mod:`~polynav.store.map_tables`, :mod:`~polynav.store.point_tables` and
    :mod:`~polynav.store.task_tables` and :mod:`~polynav.store.user_tables` (the native
    API's users), over
    :mod:`~polynav.store.database`.
    """

    # ---------------------------------------------------------------- life cycle

    @classmethod
    def open(cls, data_dir: Path | str, *, seed_world: World | None = None) -> SiteStore:
        """Open (creating if needed) the site store in ``data_dir``.

        Creates the folder, ``site.db`` and ``maps/``, applies pending schema migrations,
        removes map files left behind by a crash, and, if the store has never been seeded and
        holds no floor or map, copies ``seed_world`` into it (floors, maps, points) in one
        transaction. Reopening never seeds again, whatever was edited or deleted since.

        Args:
            data_dir: the robot's data directory.
            seed_world: the site to start from on a fresh directory (the demo world); ``None``
                leaves a fresh store empty.

        Raises:
            StorageError: the folder or database cannot be created or read, or was written by
                a newer polynav.
        """
        folder = Path(data_dir)
        try:
            (folder / MAPS_DIR).mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise StorageError(f"cannot create the data directory {folder}: {exc}") from exc
        conn = connect(folder / DB_FILE)
        try:
            migrate(conn)
            store = cls(folder, conn)
            store._remove_orphan_files()
            if seed_world is not None:
                store._seed(seed_plan(seed_world))
        except BaseException:
            conn.close()
            raise
        return store

    def close(self) -> None:
        """Close the database; later calls raise StorageError. Closing twice is harmless."""
        with self._lock:
            if self._conn is not None:
                self._conn.close()
                self._conn = None

    def __enter__(self) -> SiteStore:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()

    @property
    def data_dir(self) -> Path:
        """The data directory this store lives in."""
        return self._data_dir

    # ---------------------------------------------------------------- routes, connections

    def routes(self, map_name: str) -> list[RouteRecord]:
        """The route graphs of a map, by name.

        Raises:
            NotFound: no such map.
        """
        rows = self._map_rows("routes", "name, map_name, geometry", map_name, "name")
        return [RouteRecord(r[0], r[1], from_json(r[2])) for r in rows]

    def set_routes(self, map_name: str, routes: Sequence[RouteRecord]) -> list[RouteRecord]:
        """Replace all route graphs of a map at once.

        Raises:
            InvalidRequest: a route names another map, a name is empty or repeated, or the
                geometry is not JSON.
            NotFound: no such map.
        """
        rows: list[tuple[str, str, str]] = []
        seen: set[str] = set()
        for route in routes:
            check_name("route.name", route.name)
            if route.map_name != map_name:
                raise InvalidRequest(
                    "route.map_name", f"route {route.name!r} is on {route.map_name!r}"
                )
            if route.name in seen:
                raise InvalidRequest("route.name", f"{route.name!r} appears twice")
            seen.add(route.name)
            rows.append((map_name, route.name, to_json(f"route.{route.name}", route.geometry)))
        self._replace_map_rows("routes", "name, geometry", map_name, rows)
        return self.routes(map_name)

    def connections(self) -> list[ConnectionRecord]:
        """All connections between maps, by name."""
        with self._read() as conn:
            rows = conn.execute("SELECT name, data FROM connections ORDER BY name").fetchall()
        return [ConnectionRecord(r[0], from_json(r[1])) for r in rows]

    def set_connections(self, connections: Sequence[ConnectionRecord]) -> list[ConnectionRecord]:
        """Replace all connections at once.

        Raises:
            InvalidRequest: a name is empty or repeated, or the data is not JSON.
        """
        rows: list[tuple[str, str]] = []
        seen: set[str] = set()
        for item in connections:
            check_name("connection.name", item.name)
            if item.name in seen:
                raise InvalidRequest("connection.name", f"{item.name!r} appears twice")
            seen.add(item.name)
            rows.append((item.name, to_json(f"connection.{item.name}", item.data)))
        with self._write() as conn:
            conn.execute("DELETE FROM connections")
            conn.executemany("INSERT INTO connections (name, data) VALUES (?, ?)", rows)
        return self.connections()

    # ---------------------------------------------------------------- settings

    def settings(self) -> dict[str, Any]:
        """All stored settings, key to JSON value (validation is the runtime's job)."""
        with self._read() as conn:
            rows = conn.execute("SELECT key, value FROM settings ORDER BY key").fetchall()
        return {r[0]: from_json(r[1]) for r in rows}

    def update_settings(self, changes: Mapping[str, Any]) -> dict[str, Any]:
        """Store ``changes`` (other keys keep their values) and return all settings.

        Raises:
            InvalidRequest: a key is empty or padded, or a value is not JSON (NaN included).
        """
        rows = []
        for key, value in changes.items():
            check_name("settings", key)
            rows.append((key, to_json(f"settings.{key}", value)))
        with self._write() as conn:
            conn.executemany(
                "INSERT INTO settings (key, value) VALUES (?, ?) "
                "ON CONFLICT (key) DO UPDATE SET value = excluded.value",
                rows,
            )
            stored = conn.execute("SELECT key, value FROM settings ORDER BY key").fetchall()
        return {r[0]: from_json(r[1]) for r in stored}

    # ---------------------------------------------------------------- seeding

    def _seed(self, plan: SeedPlan) -> None:
        """Write ``plan`` in one transaction if the store was never seeded and holds no map."""
        with self._lock:
            written: list[str] = []
            try:
                with self._write() as conn:
                    seeded = conn.execute(
                        "SELECT value FROM meta WHERE key = ?", (_SEEDED_KEY,)
                    ).fetchone()
                    has_maps = conn.execute("SELECT 1 FROM maps LIMIT 1").fetchone()
                    has_floors = conn.execute("SELECT 1 FROM floors LIMIT 1").fetchone()
                    if seeded is not None or has_maps is not None or has_floors is not None:
                        return
                    conn.executemany(
                        "INSERT INTO floors (name, level, map_name) VALUES (?, ?, ?)",
                        [(f.name, f.level, f.map_name) for f in plan.floors],
                    )
                    for item in plan.maps:
                        file = self._write_map_files(conn, item.name, item.grid)
                        written.append(file)
                        conn.execute(
                            f"INSERT INTO maps ({MAP_COLUMNS}, file) VALUES (?,?,?,?,?,?,?,?,?)",
                            (item.name, item.floor, *info_columns(item.grid), file),
                        )
                    conn.executemany(
                        "INSERT INTO points "
                        "(map_name, name, x, y, theta, kind, number, custom_type) "
                        "VALUES (?, ?, ?, ?, ?, ?, ?, ?)",
                        [point_columns(p) for p in plan.points],
                    )
                    conn.executemany(
                        "INSERT INTO connections (name, data) VALUES (?, ?)",
                        [(c.name, to_json(f"connection.{c.name}", c.data))
                         for c in plan.connections],
                    )
                    conn.execute(
                        "INSERT INTO meta (key, value) VALUES (?, ?)", (_SEEDED_KEY, plan.source)
                    )
            except BaseException:
                for file in written:
                    self._remove_map_files(file)
                raise
            log.info(
                "seeded the site from world %s: %d floors, %d maps, %d points",
                plan.source,
                len(plan.floors),
                len(plan.maps),
                len(plan.points),
            )
