"""An in-memory stand-in for the site store, with the methods the runtime reads.

Built from a world the way the real store seeds itself: one map per floor, the floors' points.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from polynav.errors import Conflict, NotFound
from polynav.geometry import Pose2D
from polynav.maps.keepout import Keepout
from polynav.maps.map import Map
from polynav.site import Point
from polynav.worlds.world import World


@dataclass(frozen=True, slots=True)
class FloorRecord:
    name: str
    level: int
    map_name: str


@dataclass(frozen=True, slots=True)
class MapRecord:
    name: str
    floor: str | None
    resolution: float
    width: int
    height: int
    origin: Pose2D


class FakeStore:
    def __init__(self, world: World) -> None:
        self._floors = [FloorRecord(f.name, f.level, f.map_name) for f in world.floors]
        self._maps = {f.map_name: (f.name, f.map) for f in world.floors}
        self._points = [p for f in world.floors for p in f.points]
        self._keepouts: dict[str, list[Keepout]] = {}
        self._settings: dict[str, object] = {}

    def floors(self) -> list[FloorRecord]:
        return list(self._floors)

    def maps(self) -> list[MapRecord]:
        return [self.map_record(name) for name in self._maps]

    def map_record(self, name: str) -> MapRecord:
        if name not in self._maps:
            raise NotFound("map", name)
        floor, grid = self._maps[name]
        info = grid.info
        return MapRecord(name, floor, info.resolution, info.width, info.height, info.origin)

    def load_map(self, name: str) -> Map:
        self.map_record(name)
        return self._maps[name][1]

    def points(self, *, map_name: str | None = None, floor: str | None = None) -> list[Point]:
        maps = {f.map_name for f in self._floors if floor is None or f.name == floor}
        return [
            p for p in self._points
            if p.map_name in maps and (map_name is None or p.map_name == map_name)
        ]

    def point(self, map_name: str, name: str) -> Point:
        for p in self._points:
            if p.map_name == map_name and p.name == name:
                return p
        raise NotFound("point", name)

    def find_point(self, name: str, *, map_name: str | None = None) -> Point:
        found = [p for p in self._points if p.name == name and map_name in (None, p.map_name)]
        if not found:
            raise NotFound("point", name)
        if len(found) > 1:
            raise Conflict(f"point {name!r} is on several maps")
        return found[0]

    def keepouts(self, map_name: str) -> list[Keepout]:
        return list(self._keepouts.get(map_name, []))

    def set_keepouts(self, map_name: str, keepouts: list[Keepout]) -> None:
        self._keepouts[map_name] = list(keepouts)

    def settings(self) -> dict[str, object]:
        return dict(self._settings)

    def update_settings(self, changes: Mapping[str, object]) -> dict[str, object]:
        self._settings.update(changes)
        return dict(self._settings)
