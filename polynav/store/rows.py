"""Rows of the site database: names checked, records to columns and back, the connection.

What every table of :mod:`polynav.store.site_store` shares; nothing here holds state.
"""

from __future__ import annotations

import json
import logging
import math
import re
import sqlite3
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from polynav.errors import InvalidRequest, StorageError
from polynav.geometry import Pose2D
from polynav.maps.map import FREE, OCCUPIED, UNKNOWN, Map
from polynav.site import Point, PointKind
from polynav.store.records import MapRecord

log = logging.getLogger(__name__)


BUSY_TIMEOUT = 10.0  # [s] how long a write waits for another process's transaction
MAX_NAME = 200
INT64_MIN, INT64_MAX = -(2**63), 2**63 - 1
POINT_COLUMNS = "p.map_name, p.name, p.x, p.y, p.theta, p.kind, p.number, p.custom_type"
MAP_COLUMNS = "name, floor, resolution, width, height, origin_x, origin_y, origin_theta"



def connect(path: Path) -> sqlite3.Connection:
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


def check_name(field: str, name: object) -> None:
    if not isinstance(name, str) or not name or name != name.strip():
        raise InvalidRequest(field, f"expected a non-empty name without outer spaces, got {name!r}")
    if len(name) > MAX_NAME:
        raise InvalidRequest(field, f"longer than {MAX_NAME} characters")
    if any(ord(c) < 32 or ord(c) == 127 for c in name):
        raise InvalidRequest(field, "control characters are not allowed")


def point_columns(
    point: Point,
) -> tuple[str, str, float, float, float, str, int | None, int | None]:
    """The row of ``point``, validated."""
    if not isinstance(point, Point):
        raise InvalidRequest("point", f"expected a Point, got {type(point).__name__}")
    check_name("point.name", point.name)
    check_name("point.map_name", point.map_name)
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
        if value is not None and not INT64_MIN <= value <= INT64_MAX:
            raise InvalidRequest(field, f"must fit in 64 bits, got {value}")
    if custom is not None and point.kind is not PointKind.CUSTOM:
        raise InvalidRequest("point.custom_type", "only a custom point has a custom type")
    return (point.map_name, point.name, x, y, theta, point.kind.value, number, custom)


def point_from_row(row: Sequence[Any]) -> Point:
    map_name, name, x, y, theta, kind, number, custom_type = row
    try:
        point_kind = PointKind(kind)
    except ValueError as exc:
        raise StorageError(f"point {map_name}/{name} has an unknown kind {kind!r}") from exc
    return Point(name, map_name, Pose2D(x, y, theta), point_kind, number, custom_type)


def point_exists(conn: sqlite3.Connection, map_name: str, name: str) -> bool:
    row = conn.execute(
        "SELECT 1 FROM points WHERE map_name = ? AND name = ?", (map_name, name)
    ).fetchone()
    return row is not None


def map_record_from_row(row: Sequence[Any]) -> MapRecord:
    name, floor, resolution, width, height, ox, oy, otheta = row
    return MapRecord(
        name, floor, float(resolution), int(width), int(height), Pose2D(ox, oy, otheta)
    )


def info_columns(grid: Map) -> tuple[float, int, int, float, float, float]:
    info = grid.info
    return (
        float(info.resolution),
        int(info.width),
        int(info.height),
        float(info.origin.x),
        float(info.origin.y),
        float(info.origin.theta),
    )


def map_mode(grid: Map) -> str:
    """Trinary (what ROS tools expect) when that is exact, else scale (exact for 0..100)."""
    data = grid.data
    trinary = (data == FREE) | (data == OCCUPIED) | (data == UNKNOWN)
    return "trinary" if bool(np.all(trinary)) else "scale"


def slug(name: str) -> str:
    """A file-name-safe hint of the map's name; the serial after it makes the name unique."""
    return re.sub(r"[^A-Za-z0-9_-]+", "_", name)[:40].strip("_") or "map"


def image_name(yaml_file: str) -> str:
    return yaml_file[: -len(".yaml")] + ".png"


def to_json(field: str, value: object) -> str:
    try:
        return json.dumps(value, allow_nan=False, sort_keys=True)
    except (TypeError, ValueError) as exc:
        raise InvalidRequest(field, f"not a JSON value: {exc}") from exc


def from_json(text: str) -> Any:
    try:
        return json.loads(text)
    except ValueError as exc:
        raise StorageError(f"damaged JSON in the site database: {exc}") from exc
