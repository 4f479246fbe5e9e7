"""Editing the map in use through the androidmsg interface (ros1-nav-iface §3.8-3.11):
``/set_shape`` (virtual walls: polylines, closed polygons, circles), ``/set_region`` (special
regions), ``/point_set`` and ``/delete_test_point``.

Walls are the site's keepouts of the map in use, applied to the running costmap at once;
``/androidmsg_virtualmapstatus`` says 62 or 63 and ``/wall_update`` tells clients to read the
map again. A ``shapeId`` above 0 deletes that shape; absent, 0 or negative adds one (A22).
A special region is a guided zone among the map's keepouts: the robot crosses it only along
its route (a lane ``2 * radius`` wide, 1.2 m when the radius is 0); its waiting points are kept
with it for the fleet.
"""

from __future__ import annotations

from typing import Any

from polynav.errors import PolynavError
from polynav.maps.keepout import CircleZone, ForbiddenZone, GuidedZone, Keepout, VirtualWall
from polynav.protocols.ros_graph import Graph, Message, RosError, Service
from polynav.protocols.rosbridge.androidmsg import ids
from polynav.protocols.rosbridge.androidmsg.status import VIRTUAL_MAP, WALL_UPDATE, Entries
from polynav.site import Point, PointKind

#: /point_set point_mode -> the kind of point it adds (§3.10).
POINT_MODES = {0: PointKind.GENERAL, 1: PointKind.CHARGER, 2: PointKind.INITIAL,
               3: PointKind.LIFT_OUTSIDE}
# /point_set results (§3.10).
ADDED, MAP_NOT_READY, NO_MAP_LIST, EMPTY_NAME, BAD_NAME = 0, 1, 2, 3, 4
# /delete_test_point results (§3.11).
DELETED, IN_USE = 0, 4
#: A special region's lane when the request's radius is 0 [m].
DEFAULT_LANE_WIDTH = 1.2


class Editing(Entries):
    """The map-editing entries over one runtime."""

    def declare(self, graph: Graph) -> None:
        graph.add_service(Service("/set_shape", "map_msgs/SetShape", self.set_shape))
        graph.add_service(Service("/set_region", "map_msgs/SetRegion", self.set_region))
        graph.add_service(Service("/point_set", "map_msgs/PointSet", self.point_set))
        graph.add_service(Service("/delete_test_point", "map_msgs/DeleteTestPoint",
                                  self.delete_test_point))

    # -- virtual walls -------------------------------------------------------------------------

    def set_shape(self, args: Message) -> Message:
        try:
            self._set_shape(args)
        except RosError:
            self._status.code(VIRTUAL_MAP, 63)
            raise
        self._status.code(VIRTUAL_MAP, 62)
        self._status.code(WALL_UPDATE, 1)
        return {"success": True}

    def _set_shape(self, args: Message) -> None:
        name = self._map_in_use()
        current = list(self._store.keepouts(name))
        shape_id = args.get("shapeId")
        if shape_id is not None and ids.number(args, "shapeId") > 0:
            kept = [k for k in current if ids.shape_id(k) != shape_id]
            if len(kept) == len(current):
                raise RosError(f"no virtual wall {shape_id} on map {name!r}")
            self._save(name, kept)
            return
        self._save(name, [*current, _shape(args)])

    def _save(self, name: str, keepouts: list[Keepout]) -> None:
        try:
            self._store.set_keepouts(name, keepouts)
            self._runtime.reload_keepouts()
        except PolynavError as exc:
            raise RosError(str(exc)) from None

    # -- special regions -----------------------------------------------------------------------

    def set_region(self, args: Message) -> Message:
        name = self._map_in_use()
        current = list(self._store.keepouts(name))
        shape_id = args.get("shapeId")
        if shape_id is not None and ids.number(args, "shapeId") > 0:
            kept = [k for k in current
                    if not (isinstance(k, GuidedZone) and ids.shape_id(k) == shape_id)]
            if len(kept) == len(current):
                raise RosError(f"no special region {shape_id} on map {name!r}")
        else:
            if args.get("type") != "lines" or args.get("closed") is not True:
                raise RosError("a special region is 'lines' with 'closed' true (§3.9)")
            radius = args.get("radius", 0.0)
            if isinstance(radius, bool) or not isinstance(radius, (int, float)) or radius < 0:
                raise RosError(f"'radius' must be >= 0 [m], got {radius!r}")
            try:
                region = GuidedZone(
                    tuple(_points(args, "points", least=3)),
                    tuple(_points(args, "points2", least=2)),
                    2.0 * radius if radius > 0 else DEFAULT_LANE_WIDTH,
                    tuple(_points(args, "startPointWaits", least=0)),
                    tuple(_points(args, "endPointWaits", least=0)))
            except PolynavError as exc:
                raise RosError(str(exc)) from None
            kept = [*current, region]
        self._save(name, kept)
        self._status.code(WALL_UPDATE, 1)
        return {"success": True}

    # -- points --------------------------------------------------------------------------------

    def point_set(self, args: Message) -> Message:
        mode = ids.number(args, "point_mode")
        if mode not in POINT_MODES:
            raise RosError(f"'point_mode' must be 0-3, got {mode}")
        point_name = args.get("point_name")
        snap = self._runtime.status()
        if snap.mode != "navigating" or snap.map is None or snap.localization_state != "tracking":
            return {"result": MAP_NOT_READY}
        if mode == 3 and isinstance(args.get("point_id"), int) and args["point_id"] > 0:
            return self._delete_lift_point(snap.map, int(args["point_id"]))
        if not isinstance(point_name, str) or not point_name.strip():
            return {"result": EMPTY_NAME}
        point_name = point_name.strip()
        if point_name in {p.name for p in self._store.points(map_name=snap.map)}:
            return {"result": BAD_NAME}
        kind = POINT_MODES[mode]
        try:
            self._store.add_point(Point(point_name, snap.map, snap.pose, kind))
        except PolynavError:
            return {"result": BAD_NAME}
        return {"result": ADDED}

    def _delete_lift_point(self, map_name: str, point_id: int) -> Message:
        for p in self._store.points(map_name=map_name):
            if ids.point_id(p) == point_id and p.kind in (PointKind.LIFT_OUTSIDE,
                                                          PointKind.LIFT_INSIDE):
                self._store.delete_point(map_name, p.name)
                return {"result": ADDED}
        return {"result": NO_MAP_LIST}

    def delete_test_point(self, args: Message) -> Message:
        point = self._site.point(*(ids.number(args, k) for k in ("floor_id", "map_id",
                                                                 "point_id")))
        if point.kind in (PointKind.INITIAL, PointKind.CHARGER):
            raise RosError(f"point {point.name!r} is the map's {point.kind.value} point: it "
                           "cannot be deleted")
        if self._runtime.status().goal_point == point.name:
            return {"result": IN_USE}
        self._store.delete_point(point.map_name, point.name)
        return {"result": DELETED}


def _points(args: Message, key: str, *, least: int) -> list[tuple[float, float]]:
    raw = args.get(key, [])
    if not isinstance(raw, list):
        raise RosError(f"'{key}' must be an array of points")
    out: list[tuple[float, float]] = []
    for i, p in enumerate(raw):
        if not isinstance(p, dict):
            raise RosError(f"'{key}[{i}]' must be a point")
        xy = [p.get("x"), p.get("y")]
        if any(isinstance(v, bool) or not isinstance(v, (int, float)) for v in xy):
            raise RosError(f"'{key}[{i}]' needs numbers x and y")
        out.append((float(xy[0]), float(xy[1])))  # type: ignore[arg-type]
    if len(out) < least:
        raise RosError(f"'{key}' needs at least {least} points, got {len(out)}")
    return out


def _shape(args: dict[str, Any]) -> Keepout:
    kind = args.get("type")
    if kind == "circle":
        (x, y), = _points(args, "points", least=1)[:1]
        radius = args.get("radius")
        if isinstance(radius, bool) or not isinstance(radius, (int, float)) or not radius > 0:
            raise RosError(f"a circle needs a 'radius' > 0 [m], got {radius!r}")
        return CircleZone(x, y, float(radius))
    if kind == "lines":
        closed = args.get("closed", False)
        if not isinstance(closed, bool):
            raise RosError("'closed' must be true or false")
        pts = _points(args, "points", least=3 if closed else 2)
        return ForbiddenZone(tuple(pts)) if closed else VirtualWall(tuple(pts))
    raise RosError(f"'type' must be 'lines' or 'circle', got {kind!r}")
