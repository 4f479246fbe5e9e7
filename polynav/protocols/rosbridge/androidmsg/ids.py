"""The numeric ids of the androidmsg interface's floors, maps, points and shapes.

The interface addresses everything by number (``floor_id``, ``map_id``, ``point_id``,
``shapeId``); polynav's site names things. The numbers are derived, never stored, so they stay
the same across restarts and across the other dialects' edits (docs/decisions.md, "androidmsg
ids"): a floor's id is its level; a point's id is its site number when it has one; a map's, a
numberless point's and a shape's id is a CRC-32 of its name or geometry, folded into 1 ..
2^31-1.
"""

from __future__ import annotations

import contextlib
import json
import zlib
from dataclasses import asdict
from typing import Any

from polynav.errors import NotFound
from polynav.maps.keepout import Keepout
from polynav.protocols.ros_graph import RosError
from polynav.site import Point
from polynav.store.records import FloorRecord, MapRecord
from polynav.store.site_store import SiteStore


def _fold(text: str) -> int:
    return zlib.crc32(text.encode("utf-8")) % 2_147_483_646 + 1


def map_id(name: str) -> int:
    return _fold(f"map:{name}")


def point_id(point: Point) -> int:
    return point.number if point.number is not None else _fold(
        f"point:{point.map_name}:{point.name}")


def shape_id(shape: Keepout) -> int:
    return _fold(f"shape:{type(shape).__name__}:{json.dumps(asdict(shape), sort_keys=True)}")


def number(args: dict[str, Any], key: str) -> int:
    """An integer field of a request.

    Raises:
        RosError: missing or not an integer.
    """
    value = args.get(key)
    if isinstance(value, bool) or not isinstance(value, int):
        if isinstance(value, float) and value.is_integer():
            return int(value)
        raise RosError(f"'{key}' must be an integer, got {value!r}")
    return value


def text(args: dict[str, Any], key: str, *, empty: bool = False) -> str:
    value = args.get(key)
    if not isinstance(value, str) or (not empty and not value.strip()):
        raise RosError(f"'{key}' must be a non-empty string, got {value!r}")
    return value.strip()


class Site:
    """The site read through the interface's ids."""

    def __init__(self, store: SiteStore) -> None:
        self.store = store

    def floors(self) -> list[FloorRecord]:
        return sorted(self.store.floors(), key=lambda f: (f.level, f.name))

    def floor_named(self, name: str | None) -> FloorRecord | None:
        return next((f for f in self.floors() if f.name == name), None)

    def floor_by_id(self, floor_id: int) -> FloorRecord:
        for floor in self.floors():
            if floor.level == floor_id:
                return floor
        raise RosError(f"no floor {floor_id}")

    def maps_of(self, floor: FloorRecord) -> list[MapRecord]:
        """The floor's maps: those recorded on it, and its own map."""
        maps = {m.name: m for m in self.store.maps() if m.floor == floor.name}
        if floor.map_name not in maps:
            with contextlib.suppress(NotFound):
                maps[floor.map_name] = self.store.map_record(floor.map_name)
        return sorted(maps.values(), key=lambda m: m.name)

    def map_name(self, floor_id: int, the_map_id: int) -> str:
        """The name of map ``the_map_id`` of floor ``floor_id``.

        Raises:
            RosError: no such floor, or no such map on it.
        """
        floor = self.floor_by_id(floor_id)
        for record in self.maps_of(floor):
            if map_id(record.name) == the_map_id:
                return record.name
        raise RosError(f"no map {the_map_id} on floor {floor_id}")

    def point(self, floor_id: int, the_map_id: int, the_point_id: int) -> Point:
        """Point ``the_point_id`` of that map.

        Raises:
            RosError: no such floor, map or point.
        """
        name = self.map_name(floor_id, the_map_id)
        for point in self.store.points(map_name=name):
            if point_id(point) == the_point_id:
                return point
        raise RosError(f"no point {the_point_id} on map {the_map_id} of floor {floor_id}")

    def floor_of_map(self, map_name: str | None) -> FloorRecord | None:
        """The floor a map is on (its record's floor, or the floor whose map it is)."""
        if map_name is None:
            return None
        floors = self.floors()
        with contextlib.suppress(NotFound):
            recorded = self.store.map_record(map_name).floor
            for floor in floors:
                if floor.name == recorded:
                    return floor
        return next((f for f in floors if f.map_name == map_name), None)
