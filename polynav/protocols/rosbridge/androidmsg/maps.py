"""Floors and maps of the androidmsg interface (ros1-nav-iface §3.1, §3.2, §3.12-3.16):
``/get_maps``, ``/publish_map``, ``/clear_map``, ``/save_map``, ``/save_ext_map``,
``/delete_map``, ``/delete_allmap``.

Floors are the site's floors (id: the level), maps the site's maps; a new map is built by the
runtime's mapping mode (``/clear_map`` starts it, ``/save_map`` saves it into a floor). The
"erased" map of ``/save_ext_map`` is a picture in the ROS map_server convention (A29: PNG or
PGM, the size of the map it replaces; white free, black occupied, grey unknown).
"""

from __future__ import annotations

import base64
import binascii
import io
import json
from typing import Any

import numpy as np
from PIL import Image, UnidentifiedImageError

from polynav.errors import NotFound, PolynavError
from polynav.maps.keepout import CircleZone, ForbiddenZone, GuidedZone, VirtualWall
from polynav.maps.map import Map
from polynav.protocols.ros_graph import Graph, Message, RosError, Service
from polynav.protocols.rosbridge.androidmsg import ids
from polynav.protocols.rosbridge.androidmsg.status import (
    MAP_LOAD,
    WALL_UPDATE,
    Entries,
)
from polynav.site import Point, PointKind
from polynav.store.records import FloorRecord

#: ROS map_server's thresholds for a trinary picture (occupied above, free below).
OCCUPIED_THRESHOLD = 0.65
FREE_THRESHOLD = 0.196
#: The largest picture ``/save_ext_map`` takes [bytes of base64].
MAX_PICTURE = 16 * 1024 * 1024

_SYSTEM = {PointKind.INITIAL: "initial", PointKind.CHARGER: "charge"}


class Maps(Entries):
    """The floor and map entries over one runtime."""

    def declare(self, graph: Graph) -> None:
        for name, kind, call in (
            ("/get_maps", "std_srvs/Trigger", self.get_maps),
            ("/publish_map", "map_msgs/PublishMap", self.publish_map),
            ("/clear_map", "map_msgs/ClearMap", self.clear_map),
            ("/save_map", "map_msgs/SaveMap", self.save_map),
            ("/save_ext_map", "map_msgs/SaveMapString", self.save_ext_map),
            ("/delete_map", "map_msgs/DeleteMap", self.delete_map),
            ("/delete_allmap", "map_msgs/DeleteMap", self.delete_all),
        ):
            graph.add_service(Service(name, kind, call))

    # -- reading -------------------------------------------------------------------------------

    def get_maps(self, args: Message) -> Message:
        snap = self._runtime.status()
        here = self._site.floor_of_map(snap.map) or self._site.floor_named(snap.floor)
        floors = [self._floor(f) for f in self._site.floors()]
        body = {"defaultFloor": here.level if here else 0, "floors": floors}
        return {"success": True, "message": json.dumps(body, ensure_ascii=False)}

    def _floor(self, floor: FloorRecord) -> dict[str, Any]:
        return {"floorId": floor.level, "floorName": floor.name,
                "defaultmap": ids.map_id(floor.map_name),
                "maps": [self._map(m.name) for m in self._site.maps_of(floor)]}

    def _map(self, name: str) -> dict[str, Any]:
        points = self._store.points(map_name=name)
        system = [p for p in points if p.kind in _SYSTEM]
        first = {kind: next((ids.point_id(p) for p in points if p.kind is kind), 0)
                 for kind in _SYSTEM}
        return {
            "mapid": ids.map_id(name),
            "initialid": first[PointKind.INITIAL],
            "chargeid": first[PointKind.CHARGER],
            "mapName": name,
            "systemPoints": [{**_point(p), "type": _SYSTEM[p.kind]} for p in system],
            "shapeAreas": [_shape(k) for k in self._store.keepouts(name)],
            "mapFile": str(self._store.map_image_path(name)),
            "points": [_point(p) for p in points if p.kind not in _SYSTEM],
        }

    # -- switching -----------------------------------------------------------------------------

    def publish_map(self, args: Message) -> Message:
        kind = ids.number(args, "type")
        if kind not in (0, 1):
            raise RosError(f"'type' must be 0 (default and load) or 1 (default only), got {kind}")
        floor = self._site.floor_by_id(ids.number(args, "floor_id"))
        name = self._site.map_name(floor.level, ids.number(args, "map_id"))
        self._store.save_floor(FloorRecord(floor.name, floor.level, name))
        if kind == 0:
            try:
                self._runtime.start_navigation(name)
            except PolynavError as exc:
                self._status.code(MAP_LOAD, 61)
                raise RosError(f"map {name!r} could not be loaded: {exc}") from None
        return {}

    # -- making maps ---------------------------------------------------------------------------

    def clear_map(self, args: Message) -> Message:
        runtime = self._runtime
        try:
            if runtime.status().mode == "navigating":
                runtime.stop_navigation()
            runtime.start_mapping()
        except PolynavError as exc:
            raise RosError(f"/clear_map: {exc}") from None
        return {"result": 0}

    def save_map(self, args: Message) -> Message:
        floor, name = self._target_floor(args)
        try:
            self._runtime.stop_mapping(name)
        except PolynavError as exc:
            raise RosError(f"/save_map: {exc}") from None
        self._file(name, floor)
        return {"status": 0, "message": f"map {name!r} saved on floor {floor.name!r}"}

    def save_ext_map(self, args: Message) -> Message:
        floor, name = self._target_floor(args)
        picture = args.get("base64")
        if not isinstance(picture, str) or not picture:
            raise RosError("'base64' must be the map picture, base64-encoded")
        if len(picture) > MAX_PICTURE:
            raise RosError(f"'base64' is over {MAX_PICTURE} bytes")
        like = self._runtime.status().map or floor.map_name
        try:
            base = self._store.load_map(name)
        except NotFound:
            base = self._store.load_map(like)
        grid = _picture_to_map(picture, base)
        self._store.save_map(name, grid, floor=floor.name)
        self._file(name, floor)
        self._status.code(WALL_UPDATE, 1)
        return {"status": 0, "message": f"map {name!r} saved on floor {floor.name!r}"}

    def _target_floor(self, args: Message) -> tuple[FloorRecord, str]:
        kind = ids.number(args, "type")
        name = ids.text(args, "map_name")
        if kind == 0:
            snap = self._runtime.status()
            floor = self._site.floor_named(snap.floor)
            if floor is None:
                raise RosError(f"the robot's floor {snap.floor!r} is not a floor of the site")
            return floor, name
        if kind == 1:
            return self._site.floor_by_id(ids.number(args, "floor_id")), name
        if kind == 2:
            floor_name = ids.text(args, "floor_name")
            if self._site.floor_named(floor_name) is not None:
                raise RosError(f"floor {floor_name!r} exists: save with type 1 and its floor_id")
            level = max((f.level for f in self._site.floors()), default=0) + 1
            return FloorRecord(floor_name, level, name), name
        raise RosError(f"'type' must be 0 (this floor), 1 (floor_id) or 2 (a new floor), "
                       f"got {kind}")

    def _file(self, name: str, floor: FloorRecord) -> None:
        """Put map ``name`` on ``floor`` (a new floor is made with it as its map)."""
        if self._site.floor_named(floor.name) is not None:
            self._store.save_map(name, self._store.load_map(name), floor=floor.name)
        else:
            self._store.save_floor(floor)

    # -- deleting ------------------------------------------------------------------------------

    def delete_map(self, args: Message) -> Message:
        floor = self._site.floor_by_id(ids.number(args, "floor_id"))
        name = self._site.map_name(floor.level, ids.number(args, "map_id"))
        self._delete(name)
        return {}

    def delete_all(self, args: Message) -> Message:
        if ids.number(args, "floor_id") != 0 or ids.number(args, "map_id") != 0:
            raise RosError("/delete_allmap takes floor_id 0 and map_id 0 (A30)")
        for record in self._store.maps():
            self._delete(record.name)
        return {}

    def _delete(self, name: str) -> None:
        if self._runtime.map_name == name:
            raise RosError(f"map {name!r} is in use: stop navigation or load another map first")
        floor = self._site.floor_of_map(name)
        try:
            if floor is not None and floor.map_name == name:
                others = [m for m in self._site.maps_of(floor) if m.name != name]
                if others:  # the floor keeps another of its maps as its own
                    self._store.save_floor(FloorRecord(floor.name, floor.level, others[0].name))
                else:  # a floor with no map left goes with it (§3.15)
                    self._store.delete_floor(floor.name)
            self._store.delete_map(name)
        except PolynavError as exc:
            raise RosError(str(exc)) from None


def _point(p: Point) -> dict[str, Any]:
    return {"pointid": ids.point_id(p), "pointName": p.name, "positionx": p.pose.x,
            "positiony": p.pose.y, "positionyaw": p.pose.theta}


def _xyz(points: tuple[tuple[float, float], ...]) -> list[dict[str, float]]:
    return [{"x": x, "y": y, "z": 0.0} for x, y in points]


def _shape(shape: object) -> dict[str, Any]:
    out: dict[str, Any] = {"shapeId": ids.shape_id(shape)}  # type: ignore[arg-type]
    if isinstance(shape, CircleZone):
        out.update(type="circle", points=_xyz(((shape.x, shape.y),)), radius=shape.radius,
                   closed=False)
    elif isinstance(shape, GuidedZone):
        out.update(type="lines", points=_xyz(shape.polygon), radius=shape.lane_width / 2.0,
                   closed=True, region=True, points2=_xyz(shape.route),
                   startPointWaits=_xyz(shape.start_waits), endPointWaits=_xyz(shape.end_waits))
    elif isinstance(shape, ForbiddenZone):
        out.update(type="lines", points=_xyz(shape.polygon), radius=0.0, closed=True)
    elif isinstance(shape, VirtualWall):
        out.update(type="lines", points=_xyz(shape.points), radius=0.0, closed=False)
    return out


def _picture_to_map(text: str, like: Map) -> Map:
    """A base64 PNG/PGM picture as a grid the size and place of ``like``.

    Raises:
        RosError: not base64, not a picture, or not the map's size.
    """
    try:
        raw = base64.b64decode(text.split(",", 1)[-1], validate=True)
        with Image.open(io.BytesIO(raw)) as img:
            grey = np.asarray(img.convert("L"), dtype=np.float64)
    except (binascii.Error, ValueError) as exc:
        raise RosError(f"'base64' is not base64: {exc}") from None
    except (UnidentifiedImageError, OSError) as exc:
        raise RosError(f"'base64' is not a PNG or PGM picture: {exc}") from None
    height, width = grey.shape
    info = like.info
    if (width, height) != (info.width, info.height):
        raise RosError(f"the picture is {width} x {height}; the map is {info.width} x "
                       f"{info.height} cells")
    occupancy = (255.0 - np.flipud(grey)) / 255.0  # the picture's top row is the map's last
    data = np.full(occupancy.shape, -1, dtype=np.int8)
    data[occupancy > OCCUPIED_THRESHOLD] = 100
    data[occupancy < FREE_THRESHOLD] = 0
    return Map(info, data)
