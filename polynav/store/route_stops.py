"""Routes with stops: a named route drawn on a map, its ordered stops, and its own keepouts.

Galileo scripts address goals as (map, path, index): a *route* (the vendor's "path") is a
drawn polyline plus an ordered list of *stops* (the vendor's "target points"), each stop a named
:class:`~polynav.site.Point` of the map, so the same points are seen by the native API and every
dialect (one store, several views). A route also owns walls (points of a virtual wall) and
areas (axis-aligned boxes); the map's keepouts are its own keepouts plus every route's walls (as
:class:`VirtualWall` polylines) and areas (as :class:`ForbiddenZone` boxes), so they shape the
costmap wherever they were drawn.

Everything lives in the site store: a route is a :class:`~polynav.store.records.RouteRecord`
whose geometry holds ``{"kind": "stops", ...}`` (routes of other kinds are left alone), its
stops are store points, its walls and areas are mirrored into the map's keepouts. Input is
checked completely before the first write, so a bad request changes nothing.

Every map has a route named :data:`DEFAULT_ROUTE` without any stored record: its stops are the
map's points other than chargers, in the store's listing order (by point number, then the order
they were added). Storing a route under that name replaces the synthesized one.
"""

from __future__ import annotations

import logging
import math
import threading
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any

from polynav.errors import InvalidRequest, NotFound
from polynav.geometry import Pose2D
from polynav.maps.keepout import ForbiddenZone, Keepout, VirtualWall
from polynav.site import Point, PointKind
from polynav.store.records import RouteRecord
from polynav.store.site_store import SiteStore

log = logging.getLogger(__name__)

DEFAULT_ROUTE = "default"
KIND = "stops"
#: Wall points further apart than this [m] start a new wall polyline (the vendor's wall file is
#: a bare list of rasterized points, 0.05 m apart in its example, with no grouping).
WALL_SPLIT = 0.3
MAX_STOPS = 256  # the serial protocol addresses goals as 0-255

Box = tuple[float, float, float, float]
Point3 = tuple[float, float, float]


@dataclass(frozen=True, slots=True)
class Stop:
    """One stop of a route.

    Attributes:
        point: the name of the map point the stop is at.
        label: the name the client gave (``""`` when it gave none; the point then has a
            generated name).
        z: the vendor's third coordinate, kept and echoed.
        error_x, error_y: allowed position error [m] at the stop.
        direction: the vendor's "loop direction" value, kept and echoed.
        owned: the point was created for this route (deleted with it).
    """

    point: str
    label: str = ""
    z: float = 0.0
    error_x: float = 0.1
    error_y: float = 0.1
    direction: int = 0
    owned: bool = False


@dataclass(frozen=True, slots=True)
class StopInput:
    """A stop as a client uploads it: a pose and the stop's extras."""

    pose: Pose2D
    label: str = ""
    z: float = 0.0
    error_x: float = 0.1
    error_y: float = 0.1
    direction: int = 0


@dataclass(frozen=True, slots=True)
class StopRoute:
    """A route with stops on one map.

    Attributes:
        map_name, name: where and what.
        polyline: the drawn route's points ``(x, y, z)`` [m], in the order drawn.
        polyline_text: the route file exactly as uploaded (``None``: none uploaded).
        stops: the ordered stops.
        walls: virtual-wall points ``(x, y)`` [m].
        areas: boxes ``(x1, y1, x2, y2)`` [m].
        stored: a stored record exists (``False`` for the synthesized default route).
    """

    map_name: str
    name: str
    polyline: tuple[Point3, ...] = ()
    polyline_text: str | None = None
    stops: tuple[Stop, ...] = ()
    walls: tuple[tuple[float, float], ...] = ()
    areas: tuple[Box, ...] = ()
    stored: bool = True
    map_points: bool = False

    def to_geometry(self) -> dict[str, Any]:
        return {
            "kind": KIND,
            "polyline": [list(p) for p in self.polyline],
            "polyline_text": self.polyline_text,
            # None: the stops are the map's points whenever read (the default route).
            "stops": None if self.map_points else [
                {"point": s.point, "label": s.label, "z": s.z, "error_x": s.error_x,
                 "error_y": s.error_y, "direction": s.direction, "owned": s.owned}
                for s in self.stops
            ],
            "walls": [list(w) for w in self.walls],
            "areas": [list(a) for a in self.areas],
        }

    @classmethod
    def from_record(cls, record: RouteRecord) -> StopRoute | None:
        """The route a record holds, or ``None`` when it is another kind of route."""
        g = record.geometry
        if not isinstance(g, dict) or g.get("kind") != KIND:
            return None
        stops = g["stops"]
        return cls(
            map_name=record.map_name,
            name=record.name,
            polyline=tuple((float(p[0]), float(p[1]), float(p[2])) for p in g["polyline"]),
            polyline_text=g.get("polyline_text"),
            stops=tuple(
                Stop(s["point"], s.get("label", ""), float(s.get("z", 0.0)),
                     float(s.get("error_x", 0.1)), float(s.get("error_y", 0.1)),
                     int(s.get("direction", 0)), bool(s.get("owned", False)))
                for s in stops or ()
            ),
            walls=tuple((float(w[0]), float(w[1])) for w in g["walls"]),
            areas=tuple((float(a[0]), float(a[1]), float(a[2]), float(a[3])) for a in g["areas"]),
            map_points=stops is None,
        )


def wall_polylines(points: Sequence[tuple[float, float]]) -> list[VirtualWall]:
    """Wall points as polylines: consecutive points closer than :data:`WALL_SPLIT` join."""
    walls: list[VirtualWall] = []
    run: list[tuple[float, float]] = []
    for p in points:
        if run and math.dist(run[-1], p) > WALL_SPLIT:
            walls.append(VirtualWall(tuple(run)))
            run = []
        run.append(p)
    if run:
        walls.append(VirtualWall(tuple(run)))
    return walls


def area_zone(box: Box) -> ForbiddenZone:
    x1, y1, x2, y2 = box
    return ForbiddenZone(((x1, y1), (x2, y1), (x2, y2), (x1, y2)))


def route_keepouts(route: StopRoute) -> list[Keepout]:
    out: list[Keepout] = list(wall_polylines(route.walls))
    out.extend(area_zone(a) for a in route.areas)
    return out


def check_box(field_name: str, box: Sequence[float]) -> Box:
    """A finite box with two distinct corners, normalized to ``x1 <= x2``, ``y1 <= y2``."""
    if len(box) != 4 or not all(math.isfinite(v) for v in box):
        raise InvalidRequest(field_name, f"a box is 4 finite numbers, got {list(box)}")
    x1, y1, x2, y2 = (float(v) for v in box)
    if x1 == x2 or y1 == y2:
        raise InvalidRequest(field_name, f"a box needs two distinct corners, got {list(box)}")
    return (min(x1, x2), min(y1, y2), max(x1, x2), max(y1, y2))


@dataclass
class RouteBook:
    """The routes with stops of a site store (a view; the store holds everything)."""

    store: SiteStore
    _lock: threading.RLock = field(default_factory=threading.RLock)

    def names(self, map_name: str) -> list[str]:
        """The map's route names: the default route first, then the stored ones by name.

        Raises:
            NotFound: no such map.
        """
        stored = [r.name for r in self._stored(map_name)]
        return [DEFAULT_ROUTE, *[n for n in stored if n != DEFAULT_ROUTE]]

    def route(self, map_name: str, name: str) -> StopRoute:
        """The route ``name`` of ``map_name``.

        Raises:
            NotFound: no such map or route.
        """
        for route in self._stored(map_name):
            if route.name == name:
                return replace(route, stops=self._map_stops(map_name)) if route.map_points \
                    else route
        if name == DEFAULT_ROUTE:
            return StopRoute(map_name, name, stops=self._map_stops(map_name), stored=False,
                             map_points=True)
        raise NotFound("path", f"{map_name}/{name}")

    def _map_stops(self, map_name: str) -> tuple[Stop, ...]:
        return tuple(
            Stop(p.name, p.name)
            for p in self.store.points(map_name=map_name)
            if p.kind is not PointKind.CHARGER
        )

    def stop_points(self, route: StopRoute) -> list[Point]:
        """The points of ``route``'s stops, in order.

        Raises:
            NotFound: a stop's point was deleted since (through another API).
        """
        points = {p.name: p for p in self.store.points(map_name=route.map_name)}
        out: list[Point] = []
        for stop in route.stops:
            point = points.get(stop.point)
            if point is None:
                raise NotFound("point", f"{route.map_name}/{stop.point}")
            out.append(point)
        return out

    def stop_point(self, map_name: str, name: str, index: int) -> Point:
        """The point of stop ``index`` of a route.

        Raises:
            NotFound: no such map, route, or stop point.
            InvalidRequest: ``index`` out of range.
        """
        route = self.route(map_name, name)
        if not 0 <= index < len(route.stops):
            raise InvalidRequest(
                "index", f"path {name!r} of map {map_name!r} has {len(route.stops)} target "
                f"points (0..{len(route.stops) - 1}), got {index}"
            )
        return self.store.point(map_name, route.stops[index].point)

    def save_polyline(
        self, map_name: str, name: str, polyline: Sequence[Point3], text: str | None
    ) -> StopRoute:
        """Create route ``name`` or replace its drawn polyline (stops and keepouts kept);
        ``text`` is the route file as uploaded, ``None`` for a polyline drawn in the console."""
        _check_route_name(name)
        with self._lock:
            route = self._existing_or_new(map_name, name)
            return self._put(replace(route, polyline=tuple(polyline), polyline_text=text,
                                     stored=True))

    def set_stops(self, map_name: str, name: str, stops: Sequence[StopInput]) -> StopRoute:
        """Replace route ``name``'s stops (the route is created if needed).

        A stop with a label reuses the map's point of that name (moved to the stop's pose) or
        creates it; an unlabelled stop gets a point named ``<route>_<index>``. Points the route
        created and no longer uses are deleted.

        Raises:
            InvalidRequest: too many stops, a bad pose, a label used twice, a generated name
                that is another point's.
            NotFound: no such map.
        """
        _check_route_name(name)
        if len(stops) > MAX_STOPS:
            raise InvalidRequest("path_data", f"at most {MAX_STOPS} target points per path")
        with self._lock:
            route = self._existing_or_new(map_name, name)
            points = {p.name: p for p in self.store.points(map_name=map_name)}
            previous_owned = set() if route.map_points else {
                s.point for s in route.stops if s.owned
            }
            planned: list[tuple[Stop, Point, bool]] = []  # (stop, point, exists)
            names: set[str] = set()
            for index, item in enumerate(stops):
                pose = item.pose
                if not all(math.isfinite(v) for v in (pose.x, pose.y, pose.theta)):
                    raise InvalidRequest("path_data", f"line {index + 1}: not finite")
                point_name = item.label or f"{name}_{index}"
                if point_name in names:
                    raise InvalidRequest(
                        "path_data", f"line {index + 1}: name {point_name!r} used twice"
                    )
                names.add(point_name)
                existing = points.get(point_name)
                owned = point_name in previous_owned or existing is None
                if not item.label and existing is not None and point_name not in previous_owned:
                    raise InvalidRequest(
                        "path_data",
                        f"line {index + 1}: generated name {point_name!r} is another point's",
                    )
                kind = existing.kind if existing is not None else PointKind.GENERAL
                point = Point(point_name, map_name, Pose2D(pose.x, pose.y, pose.theta), kind,
                              existing.number if existing is not None else None,
                              existing.custom_type if existing is not None else None)
                stop = Stop(point_name, item.label, item.z, item.error_x, item.error_y,
                            item.direction, owned)
                planned.append((stop, point, existing is not None))
            for _, point, exists in planned:
                if exists:
                    self.store.update_point(map_name, point.name, point)
                else:
                    self.store.add_point(point)
            new_route = replace(route, stops=tuple(s for s, _, _ in planned), stored=True,
                                map_points=False)
            saved = self._put(new_route)
            self._drop_unused(map_name, previous_owned - names)
            return saved

    def clear_stops(self, map_name: str, name: str) -> StopRoute:
        """Delete route ``name``'s stops (the route stays; its own points are deleted).

        Raises:
            NotFound: no such map or route.
        """
        with self._lock:
            route = self.route(map_name, name)
            owned = {s.point for s in route.stops if s.owned and not route.map_points}
            saved = self._put(replace(route, stops=(), stored=True, map_points=False))
            self._drop_unused(map_name, owned)
            return saved

    def set_walls(
        self, map_name: str, name: str, walls: Sequence[tuple[float, float]]
    ) -> StopRoute:
        """Replace route ``name``'s virtual-wall points (``[]`` deletes them)."""
        for x, y in walls:
            if not (math.isfinite(x) and math.isfinite(y)):
                raise InvalidRequest("virtual_wall", "coordinates must be finite")
        with self._lock:
            route = self._existing_or_new(map_name, name)
            return self._put(replace(route, walls=tuple(walls), stored=True))

    def set_areas(self, map_name: str, name: str, areas: Sequence[Box]) -> StopRoute:
        """Replace route ``name``'s areas (``[]`` deletes them)."""
        boxes = tuple(check_box("skip_area", a) for a in areas)
        with self._lock:
            route = self._existing_or_new(map_name, name)
            return self._put(replace(route, areas=boxes, stored=True))

    def delete(self, map_name: str, name: str) -> None:
        """Delete route ``name``, its own points and its keepouts.

        Raises:
            NotFound: no such map or stored route.
        """
        with self._lock:
            route = self.route(map_name, name)
            if not route.stored:
                raise NotFound("path", f"{map_name}/{name}")
            others = [r for r in self.store.routes(map_name) if r.name != name]
            self._sync_keepouts(map_name, old=[route], new=[])
            self.store.set_routes(map_name, others)
            if not route.map_points:
                self._drop_unused(map_name, {s.point for s in route.stops if s.owned})

    # -- internals ------------------------------------------------------------------------------

    def _stored(self, map_name: str) -> list[StopRoute]:
        out = []
        for record in self.store.routes(map_name):
            route = StopRoute.from_record(record)
            if route is not None:
                out.append(route)
        return out

    def _existing_or_new(self, map_name: str, name: str) -> StopRoute:
        try:
            return self.route(map_name, name)
        except NotFound:
            self.store.map_record(map_name)  # NotFound for an unknown map
            return StopRoute(map_name, name)

    def _put(self, route: StopRoute) -> StopRoute:
        records = self.store.routes(route.map_name)
        old = [r for r in self._stored(route.map_name) if r.name == route.name]
        others = [r for r in records if r.name != route.name]
        self._sync_keepouts(route.map_name, old=old, new=[route])
        self.store.set_routes(
            route.map_name,
            [*others, RouteRecord(route.name, route.map_name, route.to_geometry())],
        )
        return route

    def _sync_keepouts(
        self, map_name: str, *, old: Sequence[StopRoute], new: Sequence[StopRoute]
    ) -> None:
        """Replace the keepouts ``old`` routes put on the map with those of ``new``."""
        remove = [k for r in old for k in route_keepouts(r)]
        add = [k for r in new for k in route_keepouts(r)]
        if not remove and not add:
            return
        current = list(self.store.keepouts(map_name))
        for keepout in remove:
            if keepout in current:
                current.remove(keepout)
        self.store.set_keepouts(map_name, [*current, *add])

    def _drop_unused(self, map_name: str, candidates: set[str]) -> None:
        """Delete the points in ``candidates`` that no route's stop uses any more."""
        if not candidates:
            return
        used = {s.point for r in self._stored(map_name) if not r.map_points for s in r.stops}
        for name in sorted(candidates - used):
            try:
                self.store.delete_point(map_name, name)
            except NotFound:
                log.debug("route point %s/%s already gone", map_name, name)


def _check_route_name(name: str) -> None:
    if not name or name != name.strip() or len(name) > 200:
        raise InvalidRequest("path", f"a path name is 1-200 characters, unpadded, got {name!r}")
