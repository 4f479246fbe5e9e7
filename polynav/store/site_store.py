"""The site store: one robot's persistent site data in a data directory.

Layout of ``data_dir``::

    site.db            SQLite: floors, maps, points, keepouts, routes, connections, settings
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

import contextlib
import json
import logging
import math
import re
import sqlite3
import threading
from collections.abc import Callable, Iterator, Mapping, Sequence
from pathlib import Path
from types import TracebackType
from typing import TYPE_CHECKING, Any

import numpy as np

from polynav.errors import Conflict, InvalidRequest, NotFound, StorageError
from polynav.geometry import Pose2D
from polynav.maps import ros_map
from polynav.maps.keepout import Keepout
from polynav.maps.map import FREE, OCCUPIED, UNKNOWN, Map
from polynav.site import Point, PointKind
from polynav.store import keepout_codec
from polynav.store.records import ConnectionRecord, FloorRecord, MapRecord, RouteRecord
from polynav.store.schema import migrate
from polynav.store.seed import SeedPlan, seed_plan

if TYPE_CHECKING:
    from polynav.worlds.world import World

log = logging.getLogger(__name__)

DB_FILE = "site.db"
MAPS_DIR = "maps"
BUSY_TIMEOUT = 10.0  # [s] how long a write waits for another process's transaction
_MAX_NAME = 200
_INT64_MIN, _INT64_MAX = -(2**63), 2**63 - 1
_SEEDED_KEY = "seeded_from"
_SERIAL_KEY = "map_file_serial"

_POINT_COLUMNS = "p.map_name, p.name, p.x, p.y, p.theta, p.kind, p.number, p.custom_type"
_MAP_COLUMNS = "name, floor, resolution, width, height, origin_x, origin_y, origin_theta"


class SiteStore:
    """Floors, maps, points, keepouts, routes, connections and settings of one site.

    Build it with :meth:`open`. Every method either completes or changes nothing, and raises
    :class:`~polynav.errors.NotFound` (unknown map, floor, point),
    :class:`~polynav.errors.InvalidRequest` (a malformed value),
    :class:`~polynav.errors.Conflict` (a name already taken, an ambiguous name, a map in use)
    or :class:`~polynav.errors.StorageError` (the disk or database failed).
    """

    def __init__(self, data_dir: Path, conn: sqlite3.Connection) -> None:
        """Use :meth:`open`; this only wraps an already migrated connection."""
        self._data_dir = data_dir
        self._maps_dir = data_dir / MAPS_DIR
        self._conn: sqlite3.Connection | None = conn
        self._lock = threading.RLock()
        self._cache: dict[tuple[Any, ...], Any] = {}
        self._data_version: int | None = None

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
        conn = _connect(folder / DB_FILE)
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

    # ---------------------------------------------------------------- floors

    def floors(self) -> list[FloorRecord]:
        """All floors, lowest level first."""
        return list(self._cached(("floors",), self._load_floors))

    def _load_floors(self) -> tuple[FloorRecord, ...]:
        with self._read() as conn:
            rows = conn.execute(
                "SELECT name, level, map_name FROM floors ORDER BY level, name"
            ).fetchall()
        return tuple(FloorRecord(r[0], int(r[1]), r[2]) for r in rows)

    def floor(self, name: str) -> FloorRecord:
        """The floor called ``name``.

        Raises:
            NotFound: no such floor.
        """
        floors: tuple[FloorRecord, ...] = self._cached(("floors",), self._load_floors)
        for record in floors:
            if record.name == name:
                return record
        raise NotFound("floor", name)

    def save_floor(self, record: FloorRecord) -> FloorRecord:
        """Add a floor or change one (same name), and attach its map to it.

        The map named by ``record.map_name`` must exist; its ``floor`` becomes ``record.name``.

        Raises:
            InvalidRequest: empty or padded name, or a level that is not an integer.
            NotFound: the map does not exist.
        """
        _check_name("floor.name", record.name)
        if isinstance(record.level, bool) or not isinstance(record.level, int):
            raise InvalidRequest("floor.level", f"expected an integer, got {record.level!r}")
        with self._write() as conn:
            self._require_map(conn, record.map_name)
            conn.execute(
                "INSERT INTO floors (name, level, map_name) VALUES (?, ?, ?) "
                "ON CONFLICT (name) DO UPDATE SET level = excluded.level, "
                "map_name = excluded.map_name",
                (record.name, record.level, record.map_name),
            )
            conn.execute("UPDATE maps SET floor = ? WHERE name = ?", (record.name, record.map_name))
        return record

    def delete_floor(self, name: str) -> None:
        """Remove a floor; its maps stay, belonging to no floor.

        Raises:
            NotFound: no such floor.
        """
        with self._write() as conn:
            if conn.execute("DELETE FROM floors WHERE name = ?", (name,)).rowcount == 0:
                raise NotFound("floor", name)

    # ---------------------------------------------------------------- maps

    def maps(self) -> list[MapRecord]:
        """All maps, by name."""
        return list(self._cached(("maps",), self._load_maps))

    def _load_maps(self) -> tuple[MapRecord, ...]:
        with self._read() as conn:
            rows = conn.execute(f"SELECT {_MAP_COLUMNS} FROM maps ORDER BY name").fetchall()
        return tuple(_map_record(r) for r in rows)

    def map_record(self, name: str) -> MapRecord:
        """What the store knows of map ``name``, without loading its picture.

        Raises:
            NotFound: no such map.
        """
        maps: tuple[MapRecord, ...] = self._cached(("maps",), self._load_maps)
        for record in maps:
            if record.name == name:
                return record
        raise NotFound("map", name)

    def load_map(self, name: str) -> Map:
        """The occupancy grid of map ``name``, exactly as it was saved.

        Raises:
            NotFound: no such map.
            StorageError: its files are missing or damaged.
        """
        with self._lock:
            yaml_path = self._maps_dir / self._map_file(name)
            try:
                return ros_map.load_map(yaml_path)
            except InvalidRequest as first:
                # Another process may have replaced the map between the row read and the load.
                again = self._maps_dir / self._map_file(name)
                if again == yaml_path:
                    raise StorageError(f"map {name!r} is damaged: {first}") from first
                try:
                    return ros_map.load_map(again)
                except InvalidRequest as exc:
                    raise StorageError(f"map {name!r} is damaged: {exc}") from exc

    def map_image_path(self, name: str) -> Path:
        """The PNG picture of map ``name`` (ROS map_server format, top row first).

        The path changes each time the map is saved and the old file is deleted, so read it at
        once rather than keeping the path.

        Raises:
            NotFound: no such map.
        """
        return self._maps_dir / _image_name(self._map_file(name))

    def save_map(self, name: str, grid: Map, *, floor: str | None = None) -> MapRecord:
        """Save ``grid`` as map ``name``, replacing the map of that name if there is one.

        The picture is written as ROS ``map_saver`` writes it (trinary) when the grid holds
        only free / occupied / unknown, else in scale mode; both read back exactly. Points,
        keepouts and routes of a replaced map stay (they are in world coordinates).

        Args:
            name: the map's name.
            grid: the occupancy grid.
            floor: the floor the map belongs to; ``None`` keeps the floor of the map being
                replaced (none for a new map).

        Returns:
            The saved map's record.

        Raises:
            InvalidRequest: empty or padded name, or an empty grid.
            NotFound: ``floor`` does not exist.
            StorageError: the files or the row could not be written (nothing changed then).
        """
        _check_name("map.name", name)
        if not isinstance(grid, Map) or grid.info.width < 1 or grid.info.height < 1:
            raise InvalidRequest("map", "expected a Map of at least one cell")
        info = grid.info
        if not (math.isfinite(info.resolution) and info.resolution > 0.0):
            raise InvalidRequest("map.resolution", f"must be > 0, got {info.resolution}")
        with self._lock:
            written: str | None = None
            old_file: str | None = None
            try:
                with self._write() as conn:
                    if floor is not None:
                        self._require_floor(conn, floor)
                    row = conn.execute(
                        "SELECT file, floor FROM maps WHERE name = ?", (name,)
                    ).fetchone()
                    if row is not None:
                        old_file = row[0]
                        if floor is None:
                            floor = row[1]
                    written = self._write_map_files(conn, name, grid)
                    conn.execute(
                        f"INSERT INTO maps ({_MAP_COLUMNS}, file) VALUES (?,?,?,?,?,?,?,?,?) "
                        "ON CONFLICT (name) DO UPDATE SET floor = excluded.floor, "
                        "resolution = excluded.resolution, width = excluded.width, "
                        "height = excluded.height, origin_x = excluded.origin_x, "
                        "origin_y = excluded.origin_y, origin_theta = excluded.origin_theta, "
                        "file = excluded.file",
                        (name, floor, *_info_columns(grid), written),
                    )
            except BaseException:
                if written is not None:
                    self._remove_map_files(written)
                raise
            if old_file is not None:
                self._remove_map_files(old_file)
            log.info("saved map %s (%s)", name, written)
            return self.map_record(name)

    def delete_map(self, name: str) -> None:
        """Delete map ``name`` and everything drawn on it: its points, keepouts and routes.

        Raises:
            NotFound: no such map.
            Conflict: a floor uses it as its map (save another map over it, or delete the
                floor first).
        """
        with self._lock:
            with self._write() as conn:
                old_file = self._map_file_in(conn, name)
                users = [
                    r[0]
                    for r in conn.execute(
                        "SELECT name FROM floors WHERE map_name = ? ORDER BY name", (name,)
                    )
                ]
                if users:
                    raise Conflict(
                        f"map {name!r} is the map of floor {', '.join(users)}; "
                        "save another map over it or delete the floor first"
                    )
                conn.execute("DELETE FROM maps WHERE name = ?", (name,))
            self._remove_map_files(old_file)
            log.info("deleted map %s", name)

    # ---------------------------------------------------------------- points

    def points(self, *, map_name: str | None = None, floor: str | None = None) -> list[Point]:
        """Points, by map name and then in the order they were added.

        Args:
            map_name: only the points of this map.
            floor: only the points of the maps of this floor.

        Raises:
            NotFound: ``map_name`` or ``floor`` does not exist.
        """
        return list(
            self._cached(("points", map_name, floor), lambda: self._load_points(map_name, floor))
        )

    def count_points(self, *, map_name: str) -> int:
        """How many points map ``map_name`` has (counted by the database, then cached).

        Raises:
            NotFound: no such map.
        """

        def load() -> int:
            with self._read() as conn:
                self._require_map(conn, map_name)
                row = conn.execute(
                    "SELECT COUNT(*) FROM points WHERE map_name = ?", (map_name,)
                ).fetchone()
            return int(row[0])

        return int(self._cached(("count_points", map_name), load))

    def _load_points(self, map_name: str | None, floor: str | None) -> tuple[Point, ...]:
        sql = f"SELECT {_POINT_COLUMNS} FROM points p JOIN maps m ON m.name = p.map_name"
        where: list[str] = []
        args: list[str] = []
        with self._read() as conn:
            if map_name is not None:
                self._require_map(conn, map_name)
                where.append("p.map_name = ?")
                args.append(map_name)
            if floor is not None:
                self._require_floor(conn, floor)
                where.append("m.floor = ?")
                args.append(floor)
            if where:
                sql += " WHERE " + " AND ".join(where)
            rows = conn.execute(sql + " ORDER BY p.map_name, p.rowid", args).fetchall()
        return tuple(_point(r) for r in rows)

    def point(self, map_name: str, name: str) -> Point:
        """The point ``name`` of map ``map_name``.

        Raises:
            NotFound: no such map, or no such point on it.
        """
        with self._read() as conn:
            return self._point_in(conn, map_name, name)

    def find_point(self, name: str, *, map_name: str | None = None) -> Point:
        """The point called ``name``, on ``map_name`` or on whichever map has it.

        Point names are unique per map only (the demo has ``initial`` on both floors), so
        without a map the name must be unique in the site.

        Raises:
            NotFound: no point of that name (on that map).
            Conflict: several maps have a point of that name and no map was given.
        """
        if map_name is not None:
            return self.point(map_name, name)
        with self._read() as conn:
            rows = conn.execute(
                f"SELECT {_POINT_COLUMNS} FROM points p WHERE p.name = ? ORDER BY p.map_name",
                (name,),
            ).fetchall()
        if not rows:
            raise NotFound("point", name)
        if len(rows) > 1:
            maps = ", ".join(r[0] for r in rows)
            raise Conflict(f"point {name!r} is on several maps ({maps}); name the map")
        return _point(rows[0])

    def add_point(self, point: Point) -> Point:
        """Add a point.

        Raises:
            InvalidRequest: empty or padded name, non-finite pose, bad kind or number.
            NotFound: its map does not exist.
            Conflict: the map already has a point of that name.
        """
        values = _point_columns(point)
        with self._write() as conn:
            self._require_map(conn, point.map_name)
            if _point_exists(conn, point.map_name, point.name):
                raise Conflict(f"map {point.map_name!r} already has a point {point.name!r}")
            conn.execute(
                "INSERT INTO points (map_name, name, x, y, theta, kind, number, custom_type) "
                "VALUES (?, ?, ?, ?, ?, ?, ?, ?)",
                values,
            )
        return point

    def update_point(self, map_name: str, name: str, point: Point) -> Point:
        """Replace point ``name`` of ``map_name`` by ``point``: rename, move, change kind.

        ``point.map_name`` may differ from ``map_name`` (the point moves to that map). The point
        keeps its place in the listing order.

        Raises:
            InvalidRequest: ``point`` is malformed (see :meth:`add_point`).
            NotFound: the point or the target map does not exist.
            Conflict: the new name is taken on the target map.
        """
        values = _point_columns(point)
        with self._write() as conn:
            self._point_in(conn, map_name, name)
            self._require_map(conn, point.map_name)
            moved = (point.map_name, point.name) != (map_name, name)
            if moved and _point_exists(conn, point.map_name, point.name):
                raise Conflict(f"map {point.map_name!r} already has a point {point.name!r}")
            conn.execute(
                "UPDATE points SET map_name = ?, name = ?, x = ?, y = ?, theta = ?, kind = ?, "
                "number = ?, custom_type = ? WHERE map_name = ? AND name = ?",
                (*values, map_name, name),
            )
        return point

    def delete_point(self, map_name: str, name: str) -> None:
        """Delete point ``name`` of ``map_name``.

        Raises:
            NotFound: the map or the point does not exist.
        """
        with self._write() as conn:
            self._point_in(conn, map_name, name)
            conn.execute("DELETE FROM points WHERE map_name = ? AND name = ?", (map_name, name))

    # ---------------------------------------------------------------- keepouts

    def keepouts(self, map_name: str) -> list[Keepout]:
        """The virtual walls and forbidden zones of a map, in the order they were set.

        Raises:
            NotFound: no such map.
        """
        with self._read() as conn:
            self._require_map(conn, map_name)
            rows = conn.execute(
                "SELECT type, geometry FROM keepouts WHERE map_name = ? ORDER BY id",
                (map_name,),
            ).fetchall()
        return [keepout_codec.decode(r[0], r[1]) for r in rows]

    def set_keepouts(self, map_name: str, keepouts: Sequence[Keepout]) -> list[Keepout]:
        """Replace all keepouts of a map at once.

        Raises:
            InvalidRequest: an element is not a VirtualWall, ForbiddenZone or CircleZone.
            NotFound: no such map.
        """
        rows = [keepout_codec.encode(k) for k in keepouts]
        with self._write() as conn:
            self._require_map(conn, map_name)
            conn.execute("DELETE FROM keepouts WHERE map_name = ?", (map_name,))
            conn.executemany(
                "INSERT INTO keepouts (map_name, type, geometry) VALUES (?, ?, ?)",
                [(map_name, kind, geometry) for kind, geometry in rows],
            )
        return list(keepouts)

    # ---------------------------------------------------------------- routes, connections

    def routes(self, map_name: str) -> list[RouteRecord]:
        """The route graphs of a map, by name.

        Raises:
            NotFound: no such map.
        """
        with self._read() as conn:
            self._require_map(conn, map_name)
            rows = conn.execute(
                "SELECT name, map_name, geometry FROM routes WHERE map_name = ? ORDER BY name",
                (map_name,),
            ).fetchall()
        return [RouteRecord(r[0], r[1], _from_json(r[2])) for r in rows]

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
            _check_name("route.name", route.name)
            if route.map_name != map_name:
                raise InvalidRequest(
                    "route.map_name", f"route {route.name!r} is on {route.map_name!r}"
                )
            if route.name in seen:
                raise InvalidRequest("route.name", f"{route.name!r} appears twice")
            seen.add(route.name)
            rows.append((map_name, route.name, _to_json(f"route.{route.name}", route.geometry)))
        with self._write() as conn:
            self._require_map(conn, map_name)
            conn.execute("DELETE FROM routes WHERE map_name = ?", (map_name,))
            conn.executemany("INSERT INTO routes (map_name, name, geometry) VALUES (?, ?, ?)", rows)
        return self.routes(map_name)

    def connections(self) -> list[ConnectionRecord]:
        """All connections between maps, by name."""
        with self._read() as conn:
            rows = conn.execute("SELECT name, data FROM connections ORDER BY name").fetchall()
        return [ConnectionRecord(r[0], _from_json(r[1])) for r in rows]

    def set_connections(self, connections: Sequence[ConnectionRecord]) -> list[ConnectionRecord]:
        """Replace all connections at once.

        Raises:
            InvalidRequest: a name is empty or repeated, or the data is not JSON.
        """
        rows: list[tuple[str, str]] = []
        seen: set[str] = set()
        for item in connections:
            _check_name("connection.name", item.name)
            if item.name in seen:
                raise InvalidRequest("connection.name", f"{item.name!r} appears twice")
            seen.add(item.name)
            rows.append((item.name, _to_json(f"connection.{item.name}", item.data)))
        with self._write() as conn:
            conn.execute("DELETE FROM connections")
            conn.executemany("INSERT INTO connections (name, data) VALUES (?, ?)", rows)
        return self.connections()

    # ---------------------------------------------------------------- settings

    def settings(self) -> dict[str, Any]:
        """All stored settings, key to JSON value (validation is the runtime's job)."""
        with self._read() as conn:
            rows = conn.execute("SELECT key, value FROM settings ORDER BY key").fetchall()
        return {r[0]: _from_json(r[1]) for r in rows}

    def update_settings(self, changes: Mapping[str, Any]) -> dict[str, Any]:
        """Store ``changes`` (other keys keep their values) and return all settings.

        Raises:
            InvalidRequest: a key is empty or padded, or a value is not JSON (NaN included).
        """
        rows = []
        for key, value in changes.items():
            _check_name("settings", key)
            rows.append((key, _to_json(f"settings.{key}", value)))
        with self._write() as conn:
            conn.executemany(
                "INSERT INTO settings (key, value) VALUES (?, ?) "
                "ON CONFLICT (key) DO UPDATE SET value = excluded.value",
                rows,
            )
            stored = conn.execute("SELECT key, value FROM settings ORDER BY key").fetchall()
        return {r[0]: _from_json(r[1]) for r in stored}

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

    def _require_map(self, conn: sqlite3.Connection, name: str) -> None:
        if conn.execute("SELECT 1 FROM maps WHERE name = ?", (name,)).fetchone() is None:
            raise NotFound("map", name)

    def _require_floor(self, conn: sqlite3.Connection, name: str) -> None:
        if conn.execute("SELECT 1 FROM floors WHERE name = ?", (name,)).fetchone() is None:
            raise NotFound("floor", name)

    def _point_in(self, conn: sqlite3.Connection, map_name: str, name: str) -> Point:
        self._require_map(conn, map_name)
        row = conn.execute(
            f"SELECT {_POINT_COLUMNS} FROM points p WHERE p.map_name = ? AND p.name = ?",
            (map_name, name),
        ).fetchone()
        if row is None:
            raise NotFound("point", f"{map_name}/{name}")
        return _point(row)

    def _map_file(self, name: str) -> str:
        with self._read() as conn:
            return self._map_file_in(conn, name)

    def _map_file_in(self, conn: sqlite3.Connection, name: str) -> str:
        row = conn.execute("SELECT file FROM maps WHERE name = ?", (name,)).fetchone()
        if row is None:
            raise NotFound("map", name)
        return str(row[0])

    def _write_map_files(self, conn: sqlite3.Connection, name: str, grid: Map) -> str:
        """Write ``grid`` to never-used file names (inside the caller's write transaction)."""
        row = conn.execute("SELECT value FROM meta WHERE key = ?", (_SERIAL_KEY,)).fetchone()
        serial = int(row[0]) + 1
        conn.execute("UPDATE meta SET value = ? WHERE key = ?", (str(serial), _SERIAL_KEY))
        file = f"{_slug(name)}-{serial}.yaml"
        try:
            ros_map.save_map(grid, self._maps_dir / file, image_format="png", mode=_mode(grid))
        except BaseException:
            self._remove_map_files(file)
            raise
        return file

    def _remove_map_files(self, file: str) -> None:
        """Best effort: a file left behind is removed as an orphan on the next open."""
        for path in (self._maps_dir / file, self._maps_dir / _image_name(file)):
            try:
                path.unlink(missing_ok=True)
            except OSError as exc:
                log.warning("cannot remove old map file %s: %s", path, exc)

    def _remove_orphan_files(self) -> None:
        """Remove files in ``maps/`` that no map row names: leftovers of a crash mid-save.

        Runs under the write lock, so another process cannot be between writing its new map
        files and committing the row that names them.
        """
        with self._write() as conn:
            keep: set[str] = set()
            for (file,) in conn.execute("SELECT file FROM maps"):
                keep.update((file, _image_name(file)))
            try:
                entries = list(self._maps_dir.iterdir())
            except OSError as exc:
                raise StorageError(f"cannot list {self._maps_dir}: {exc}") from exc
            for path in entries:
                if path.name in keep or not path.is_file():
                    continue
                log.info("removing leftover map file %s", path)
                try:
                    path.unlink(missing_ok=True)
                except OSError as exc:
                    log.warning("cannot remove leftover map file %s: %s", path, exc)
            for file in sorted(keep):
                if not (self._maps_dir / file).is_file():
                    log.error("map file %s is missing from %s", file, self._maps_dir)

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
                            f"INSERT INTO maps ({_MAP_COLUMNS}, file) VALUES (?,?,?,?,?,?,?,?,?)",
                            (item.name, item.floor, *_info_columns(item.grid), file),
                        )
                    conn.executemany(
                        "INSERT INTO points "
                        "(map_name, name, x, y, theta, kind, number, custom_type) "
                        "VALUES (?, ?, ?, ?, ?, ?, ?, ?)",
                        [_point_columns(p) for p in plan.points],
                    )
                    conn.executemany(
                        "INSERT INTO connections (name, data) VALUES (?, ?)",
                        [(c.name, _to_json(f"connection.{c.name}", c.data))
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


def _connect(path: Path) -> sqlite3.Connection:
    try:
        conn = sqlite3.connect(
            str(path), timeout=BUSY_TIMEOUT, isolation_level=None, check_same_thread=False
        )
    except sqlite3.Error as exc:
        raise StorageError(f"cannot open the site database {path}: {exc}") from exc
    try:
        mode = conn.execute("PRAGMA journal_mode = WAL").fetchone()[0]
        if str(mode).lower() != "wal":
            raise StorageError(f"{path}: the file system does not allow WAL mode ({mode})")
        conn.execute("PRAGMA synchronous = FULL")
        conn.execute("PRAGMA foreign_keys = ON")
    except sqlite3.Error as exc:
        conn.close()
        raise StorageError(f"cannot open the site database {path}: {exc}") from exc
    except BaseException:
        conn.close()
        raise
    return conn


def _check_name(field: str, name: object) -> None:
    if not isinstance(name, str) or not name or name != name.strip():
        raise InvalidRequest(field, f"expected a non-empty name without outer spaces, got {name!r}")
    if len(name) > _MAX_NAME:
        raise InvalidRequest(field, f"longer than {_MAX_NAME} characters")
    if any(ord(c) < 32 or ord(c) == 127 for c in name):
        raise InvalidRequest(field, "control characters are not allowed")


def _point_columns(
    point: Point,
) -> tuple[str, str, float, float, float, str, int | None, int | None]:
    """The row of ``point``, validated."""
    if not isinstance(point, Point):
        raise InvalidRequest("point", f"expected a Point, got {type(point).__name__}")
    _check_name("point.name", point.name)
    _check_name("point.map_name", point.map_name)
    pose = point.pose
    try:
        x, y, theta = float(pose.x), float(pose.y), float(pose.theta)
    except (TypeError, ValueError, AttributeError) as exc:
        raise InvalidRequest("point.pose", f"expected a Pose2D of numbers, got {pose!r}") from exc
    if not (math.isfinite(x) and math.isfinite(y) and math.isfinite(theta)):
        raise InvalidRequest("point.pose", f"coordinates must be finite, got {pose}")
    if not isinstance(point.kind, PointKind):
        raise InvalidRequest("point.kind", f"expected a PointKind, got {point.kind!r}")
    number = point.number
    if number is not None and (isinstance(number, bool) or not isinstance(number, int)):
        raise InvalidRequest("point.number", f"expected an integer or None, got {number!r}")
    custom = point.custom_type
    if custom is not None and (isinstance(custom, bool) or not isinstance(custom, int)):
        raise InvalidRequest("point.custom_type", f"expected an integer or None, got {custom!r}")
    # SQLite's INTEGER is 64-bit: a larger Python int is an OverflowError in execute().
    for field, value in (("point.number", number), ("point.custom_type", custom)):
        if value is not None and not _INT64_MIN <= value <= _INT64_MAX:
            raise InvalidRequest(field, f"must fit in 64 bits, got {value}")
    if custom is not None and point.kind is not PointKind.CUSTOM:
        raise InvalidRequest("point.custom_type", "only a custom point has a custom type")
    return (point.map_name, point.name, x, y, theta, point.kind.value, number, custom)


def _point(row: Sequence[Any]) -> Point:
    map_name, name, x, y, theta, kind, number, custom_type = row
    try:
        point_kind = PointKind(kind)
    except ValueError as exc:
        raise StorageError(f"point {map_name}/{name} has an unknown kind {kind!r}") from exc
    return Point(name, map_name, Pose2D(x, y, theta), point_kind, number, custom_type)


def _point_exists(conn: sqlite3.Connection, map_name: str, name: str) -> bool:
    row = conn.execute(
        "SELECT 1 FROM points WHERE map_name = ? AND name = ?", (map_name, name)
    ).fetchone()
    return row is not None


def _map_record(row: Sequence[Any]) -> MapRecord:
    name, floor, resolution, width, height, ox, oy, otheta = row
    return MapRecord(
        name, floor, float(resolution), int(width), int(height), Pose2D(ox, oy, otheta)
    )


def _info_columns(grid: Map) -> tuple[float, int, int, float, float, float]:
    info = grid.info
    return (
        float(info.resolution),
        int(info.width),
        int(info.height),
        float(info.origin.x),
        float(info.origin.y),
        float(info.origin.theta),
    )


def _mode(grid: Map) -> str:
    """Trinary (what ROS tools expect) when that is exact, else scale (exact for 0..100)."""
    data = grid.data
    trinary = (data == FREE) | (data == OCCUPIED) | (data == UNKNOWN)
    return "trinary" if bool(np.all(trinary)) else "scale"


def _slug(name: str) -> str:
    """A file-name-safe hint of the map's name; the serial after it makes the name unique."""
    return re.sub(r"[^A-Za-z0-9_-]+", "_", name)[:40].strip("_") or "map"


def _image_name(yaml_file: str) -> str:
    return yaml_file[: -len(".yaml")] + ".png"


def _to_json(field: str, value: object) -> str:
    try:
        return json.dumps(value, allow_nan=False, sort_keys=True)
    except (TypeError, ValueError) as exc:
        raise InvalidRequest(field, f"not a JSON value: {exc}") from exc


def _from_json(text: str) -> Any:
    try:
        return json.loads(text)
    except ValueError as exc:
        raise StorageError(f"damaged JSON in the site database: {exc}") from exc
