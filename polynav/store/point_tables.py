"""Points and keepouts of the site store."""

from __future__ import annotations

import logging
from collections.abc import Sequence

from polynav.errors import Conflict, NotFound
from polynav.maps.keepout import Keepout
from polynav.site import Point
from polynav.store import keepout_codec
from polynav.store.database import SiteDatabase
from polynav.store.rows import (
    POINT_COLUMNS,
    point_columns,
    point_exists,
    point_from_row,
)

log = logging.getLogger(__name__)


class PointTables(SiteDatabase):
    """Named points and keepout zones per map."""

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
        sql = f"SELECT {POINT_COLUMNS} FROM points p JOIN maps m ON m.name = p.map_name"
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
        return tuple(point_from_row(r) for r in rows)

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
                f"SELECT {POINT_COLUMNS} FROM points p WHERE p.name = ? ORDER BY p.map_name",
                (name,),
            ).fetchall()
        if not rows:
            raise NotFound("point", name)
        if len(rows) > 1:
            maps = ", ".join(r[0] for r in rows)
            raise Conflict(f"point {name!r} is on several maps ({maps}); name the map")
        return point_from_row(rows[0])

    def add_point(self, point: Point) -> Point:
        """Add a point.

        Raises:
            InvalidRequest: empty or padded name, non-finite pose, bad kind or number.
            NotFound: its map does not exist.
            Conflict: the map already has a point of that name.
        """
        values = point_columns(point)
        with self._write() as conn:
            self._require_map(conn, point.map_name)
            if point_exists(conn, point.map_name, point.name):
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
        values = point_columns(point)
        with self._write() as conn:
            self._point_in(conn, map_name, name)
            self._require_map(conn, point.map_name)
            moved = (point.map_name, point.name) != (map_name, name)
            if moved and point_exists(conn, point.map_name, point.name):
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
        rows = self._map_rows("keepouts", "type, geometry", map_name, "id")
        return [keepout_codec.decode(r[0], r[1]) for r in rows]

    def set_keepouts(self, map_name: str, keepouts: Sequence[Keepout]) -> list[Keepout]:
        """Replace all keepouts of a map at once.

        Raises:
            InvalidRequest: an element is not a keepout shape.
            NotFound: no such map.
        """
        rows = [keepout_codec.encode(k) for k in keepouts]
        self._replace_map_rows(
            "keepouts", "type, geometry", map_name,
            [(map_name, kind, geometry) for kind, geometry in rows],
        )
        return list(keepouts)
