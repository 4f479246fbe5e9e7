"""Floors and maps of the site store, and the map files on disk."""

from __future__ import annotations

import logging
import math
import sqlite3
from pathlib import Path

from polynav.errors import Conflict, InvalidRequest, NotFound, StorageError
from polynav.maps import ros_map
from polynav.maps.map import Map
from polynav.store.database import SiteDatabase
from polynav.store.records import FloorRecord, MapRecord
from polynav.store.rows import (
    MAP_COLUMNS,
    check_name,
    image_name,
    info_columns,
    map_mode,
    map_record_from_row,
    slug,
)

log = logging.getLogger(__name__)

_SERIAL_KEY = "map_file_serial"


class MapTables(SiteDatabase):
    """Floors and maps, each map's ROS files written beside its row (see the store's docstring)."""

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
        record: FloorRecord = self._named(("floors",), self._load_floors, "floor", name)
        return record

    def save_floor(self, record: FloorRecord) -> FloorRecord:
        """Add a floor or change one (same name), and attach its map to it.

        The map named by ``record.map_name`` must exist; its ``floor`` becomes ``record.name``.

        Raises:
            InvalidRequest: empty or padded name, or a level that is not an integer.
            NotFound: the map does not exist.
        """
        check_name("floor.name", record.name)
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
            rows = conn.execute(f"SELECT {MAP_COLUMNS} FROM maps ORDER BY name").fetchall()
        return tuple(map_record_from_row(r) for r in rows)

    def map_record(self, name: str) -> MapRecord:
        """What the store knows of map ``name``, without loading its picture.

        Raises:
            NotFound: no such map.
        """
        record: MapRecord = self._named(("maps",), self._load_maps, "map", name)
        return record

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
        return self._maps_dir / image_name(self._map_file(name))

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
        check_name("map.name", name)
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
                        f"INSERT INTO maps ({MAP_COLUMNS}, file) VALUES (?,?,?,?,?,?,?,?,?) "
                        "ON CONFLICT (name) DO UPDATE SET floor = excluded.floor, "
                        "resolution = excluded.resolution, width = excluded.width, "
                        "height = excluded.height, origin_x = excluded.origin_x, "
                        "origin_y = excluded.origin_y, origin_theta = excluded.origin_theta, "
                        "file = excluded.file",
                        (name, floor, *info_columns(grid), written),
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
        file = f"{slug(name)}-{serial}.yaml"
        try:
            ros_map.save_map(grid, self._maps_dir / file, image_format="png", mode=map_mode(grid))
        except BaseException:
            self._remove_map_files(file)
            raise
        return file

    def _remove_map_files(self, file: str) -> None:
        """Best effort: a file left behind is removed as an orphan on the next open."""
        for path in (self._maps_dir / file, self._maps_dir / image_name(file)):
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
                keep.update((file, image_name(file)))
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
