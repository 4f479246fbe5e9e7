"""World folders: a ``world.yaml`` beside the ROS map files of each floor.

The layout, every length in metres and every angle in radians::

    name: demo
    robot: research-base          # optional: a built-in profile, a robot.yaml path relative to
                                  # the folder, or the profile itself as a mapping
    start: {floor: floor1, pose: {x: 3.0, y: 4.5, theta: 1.5708}}
    floors:
      - name: floor1
        level: 1
        map: floor1.yaml            # a ROS map_server YAML, relative to the folder
        map_name: floor1            # optional, defaults to the floor name
        lift: {x: 38.0, y: 22.0, width: 2.0, depth: 2.0, door_heading: -1.5708, door_width: 1.2}
        points:
          - {name: lobby, x: 4.0, y: 6.0, theta: 0.0, kind: general, number: 1}
        people:
          - {waypoints: [[10.0, 11.5], [30.0, 11.5]], speed: 1.0, radius: 0.25, loop: false}
        access_points:
          - {ssid: office, x: 12.0, y: 12.0, frequency: 2437, security: WPA2, password: pw}
        signs:                      # "no entry" signs, facing theta (seen from that side)
          - {x: 11.6, y: 13.0, theta: -1.5708}
    lifts:                          # optional: the building's lift cars
      - {name: lift_1, x: 38.0, y: 22.0, width: 2.0, depth: 2.0, door_heading: -1.5708,
         door_width: 1.2, floors: [floor1, floor2], outside: lift_1_outside,
         inside: lift_1_inside, waiting: {x: 39.0, y: 16.0}, speed: 1.0, floor_height: 3.5,
         door_time: 2.5, capacity: 2}
    doors:                          # optional: electronic doors and gates
      - {name: fire_door_1, floor: floor2, x1: 15.3, y1: 10.95, x2: 15.3, y2: 13.05,
         kind: door, open_time: 2.0, close_time: 2.0, controller: simulated}
      - {name: lobby_gate, floor: floor1, x: 10.0, y: 12.0, theta: 0.0, width: 2.0, kind: gate}
    carts:                          # optional: carts (lifted) and cabins (latched) to carry
      - {name: cart_1, kind: cart, floor: floor1, x: 8.5, y: 2.0, theta: 0.0, length: 0.9,
         width: 0.7, mass: 40.0}
      - {name: cabin_1, kind: cabin, floor: floor2, x: 4.0, y: 1.5, theta: 0.0,
         cabin_id: CAB-0001, mass: 60.0}

``kind`` takes the values of :class:`~polynav.site.PointKind` (``general``, ``charger``,
``initial``, ``lift-outside``, ``lift-inside`` ...); ``number``, ``lift``, ``people``, ``radius``,
``loop``, ``signs`` and ``access_points`` (Wi-Fi for the simulated wireless card;
``frequency`` in MHz, ``security`` and ``password`` empty for an open network) may be left out.
A lift car's ``outside`` and ``inside`` name points present on every floor it serves (the
inside one in its shaft); ``waiting``, ``speed``, ``floor_height``, ``door_time`` and
``capacity`` may be left out. A door's place is its leaf's segment (``x1, y1, x2, y2``) or its
centre, the heading it is crossed along and its width (``x, y, theta, width``); ``kind``
(``door``, the default, or ``gate``), ``open_time``, ``close_time`` [s] and ``controller``
(``simulated``) may be left out. A cart's or cabin's place is its centre and the heading a
docked robot faces (:mod:`polynav.worlds.carts`); ``length`` and ``width`` (its legs'
rectangle), ``mass`` [kg] and ``leg_radius`` may be left out, a cabin's ``cabin_id`` may not.
Ground truth is loaded with
:func:`polynav.maps.ros_map.load_map`, so any ROS map can be the reality of a simulated floor.
"""

from __future__ import annotations

import logging
import math
from pathlib import Path
from typing import Any

import yaml

from polynav import safe_yaml
from polynav.errors import InvalidRequest
from polynav.geometry import Pose2D
from polynav.maps.ros_map import load_map
from polynav.robot.profile import ProfileError, RobotProfile, load_profile, parse_profile
from polynav.site import Point, PointKind
from polynav.worlds.carts import CartKind, WorldCart
from polynav.worlds.errors import WorldFormatError
from polynav.worlds.world import (
    AccessPoint,
    DoorKind,
    LiftCar,
    LiftShaft,
    NoEntrySign,
    PersonRoute,
    World,
    WorldDoor,
    WorldFloor,
)

log = logging.getLogger(__name__)

WORLD_FILE = "world.yaml"


def read_world(folder: str | Path) -> World:
    """Load the world kept in ``folder``.

    Args:
        folder: a folder holding ``world.yaml`` and the map files it names.

    Returns:
        The world, with every floor's ground-truth map loaded.

    Raises:
        WorldFormatError: ``world.yaml`` is missing or a field is missing or invalid.
        MapFormatError: a floor's map files are missing or invalid.
    """
    root = Path(folder)
    path = root / WORLD_FILE
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise WorldFormatError(WORLD_FILE, f"{path}: no such file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise WorldFormatError(WORLD_FILE, f"{path}: cannot read: {exc}") from exc
    try:
        doc = safe_yaml.load(text)
    except yaml.YAMLError as exc:
        raise WorldFormatError(WORLD_FILE, f"{path}: not valid YAML: {exc}") from exc
    if not isinstance(doc, dict):
        raise WorldFormatError(WORLD_FILE, f"{path}: expected a mapping")

    name = _str(doc, "name", "name")
    raw_floors = doc.get("floors")
    if not isinstance(raw_floors, list) or not raw_floors:
        raise WorldFormatError("floors", "expected a non-empty list of floors")
    floors = tuple(_floor(root, f, f"floors[{n}]") for n, f in enumerate(raw_floors))
    names = [f.name for f in floors]
    if len(set(names)) != len(names):
        raise WorldFormatError("floors", f"floor names repeat: {names}")

    start = _mapping(doc.get("start"), "start")
    start_floor = _str(start, "floor", "start.floor")
    if start_floor not in names:
        raise WorldFormatError("start.floor", f"no floor {start_floor!r} (floors: {names})")
    start_pose = _pose(_mapping(start.get("pose"), "start.pose"), "start.pose")
    robot = _robot(root, doc["robot"]) if doc.get("robot") is not None else None
    lifts = tuple(_car(c, floors, f"lifts[{n}]")
                  for n, c in enumerate(_list(doc.get("lifts", []), "lifts")))
    car_names = [c.name for c in lifts]
    if len(set(car_names)) != len(car_names):
        raise WorldFormatError("lifts", f"lift names repeat: {car_names}")
    doors = tuple(_door(d, floors, f"doors[{n}]")
                  for n, d in enumerate(_list(doc.get("doors", []), "doors")))
    door_names = [d.name for d in doors]
    if len(set(door_names)) != len(door_names):
        raise WorldFormatError("doors", f"door names repeat: {door_names}")
    carts = tuple(_cart(c, floors, f"carts[{n}]")
                  for n, c in enumerate(_list(doc.get("carts", []), "carts")))
    cart_names = [c.name for c in carts]
    if len(set(cart_names)) != len(cart_names):
        raise WorldFormatError("carts", f"cart and cabin names repeat: {cart_names}")
    world = World(name=name, floors=floors, start_floor=start_floor, start_pose=start_pose,
                  robot=robot, lifts=lifts, doors=doors, carts=carts)
    log.info("loaded world %r from %s: floors %s", name, root, names)
    return world


def _robot(root: Path, raw: object) -> RobotProfile:
    """The ``robot:`` entry: a built-in profile's name, a profile file (relative to the world
    folder), or the profile inline; a fault names the profile's field (``robot.limits...``)."""
    try:
        if isinstance(raw, dict):
            return parse_profile(raw)
        if not isinstance(raw, str) or not raw:
            raise WorldFormatError("robot", f"expected a profile name, file or mapping, got "
                                            f"{raw!r}")
        local = root / raw
        return load_profile(local if local.is_file() else raw)
    except ProfileError as exc:
        raise WorldFormatError(exc.field, exc.reason) from None


def _floor(root: Path, raw: object, key: str) -> WorldFloor:
    doc = _mapping(raw, key)
    name = _str(doc, "name", f"{key}.name")
    level = doc.get("level")
    if isinstance(level, bool) or not isinstance(level, int):
        raise WorldFormatError(f"{key}.level", f"expected an integer, got {level!r}")
    map_name = doc.get("map_name", name)
    if not isinstance(map_name, str) or not map_name:
        raise WorldFormatError(f"{key}.map_name", f"expected a name, got {map_name!r}")
    grid = load_map(root / _str(doc, "map", f"{key}.map"))
    lift = None
    if doc.get("lift") is not None:
        lift = _lift(_mapping(doc["lift"], f"{key}.lift"), f"{key}.lift")
    points = tuple(
        _point(p, map_name, f"{key}.points[{n}]")
        for n, p in enumerate(_list(doc.get("points", []), f"{key}.points"))
    )
    point_names = [p.name for p in points]
    if len(set(point_names)) != len(point_names):
        raise WorldFormatError(f"{key}.points", f"point names repeat on floor {name!r}")
    people = tuple(
        _person(p, f"{key}.people[{n}]")
        for n, p in enumerate(_list(doc.get("people", []), f"{key}.people"))
    )
    access_points = tuple(
        _access_point(a, f"{key}.access_points[{n}]")
        for n, a in enumerate(_list(doc.get("access_points", []), f"{key}.access_points"))
    )
    signs = tuple(
        _sign(s, f"{key}.signs[{n}]")
        for n, s in enumerate(_list(doc.get("signs", []), f"{key}.signs"))
    )
    return WorldFloor(
        name=name, level=level, map_name=map_name, map=grid, points=points, lift=lift,
        people=people, access_points=access_points, signs=signs,
    )


def _sign(raw: object, key: str) -> NoEntrySign:
    doc = _mapping(raw, key)
    return NoEntrySign(_num(doc, "x", key), _num(doc, "y", key),
                       _num(doc, "theta", key, default=0.0))


def _access_point(raw: object, key: str) -> AccessPoint:
    doc = _mapping(raw, key)
    frequency = doc.get("frequency", 2412)
    if isinstance(frequency, bool) or not isinstance(frequency, int):
        raise WorldFormatError(f"{key}.frequency", f"expected an integer [MHz], got {frequency!r}")
    security = doc.get("security", "")
    password = doc.get("password", "")
    for field, value in (("security", security), ("password", password)):
        if not isinstance(value, str):
            raise WorldFormatError(f"{key}.{field}", f"expected a string, got {value!r}")
    ssid = _str(doc, "ssid", f"{key}.ssid")
    x, y = _num(doc, "x", key), _num(doc, "y", key)
    try:
        return AccessPoint(
            ssid=ssid,
            x=x,
            y=y,
            frequency=frequency,
            security=security,
            password=password,
        )
    except InvalidRequest as exc:
        raise WorldFormatError(f"{key}.{exc.field}", exc.reason) from None


def _lift(doc: dict[str, Any], key: str) -> LiftShaft:
    width = _num(doc, "width", key)
    depth = _num(doc, "depth", key)
    door_width = _num(doc, "door_width", key, default=1.2)
    for field, value in (("width", width), ("depth", depth), ("door_width", door_width)):
        if value <= 0.0:
            raise WorldFormatError(f"{key}.{field}", f"must be > 0, got {value}")
    return LiftShaft(
        x=_num(doc, "x", key),
        y=_num(doc, "y", key),
        width=width,
        depth=depth,
        door_heading=_num(doc, "door_heading", key, default=0.0),
        door_width=door_width,
    )


def _car(raw: object, floors: tuple[WorldFloor, ...], key: str) -> LiftCar:
    """A ``lifts:`` entry: the shaft's fields, then ``floors``, ``outside``, ``inside``, and
    optionally ``waiting: {x, y}``, ``speed``, ``floor_height``, ``door_time``, ``capacity``."""
    doc = _mapping(raw, key)
    shaft = _lift(doc, key)
    served = _list(doc.get("floors"), f"{key}.floors")
    by_name = {f.name: f for f in floors}
    for n, floor in enumerate(served):
        if floor not in by_name:
            raise WorldFormatError(f"{key}.floors[{n}]", f"no floor {floor!r}")
    outside = _str(doc, "outside", f"{key}.outside")
    inside = _str(doc, "inside", f"{key}.inside")
    for floor in served:
        names = {p.name: p for p in by_name[floor].points}
        for field, point in (("outside", outside), ("inside", inside)):
            if point not in names:
                raise WorldFormatError(f"{key}.{field}", f"no point {point!r} on {floor!r}")
        if not shaft.contains(names[inside].pose.x, names[inside].pose.y):
            raise WorldFormatError(f"{key}.inside", f"{inside!r} on {floor!r} is not in the car")
    waiting = None
    if doc.get("waiting") is not None:
        wait = _mapping(doc["waiting"], f"{key}.waiting")
        waiting = (_num(wait, "x", f"{key}.waiting"), _num(wait, "y", f"{key}.waiting"))
    capacity = doc.get("capacity", 1)
    if isinstance(capacity, bool) or not isinstance(capacity, int):
        raise WorldFormatError(f"{key}.capacity", f"expected an integer, got {capacity!r}")
    order = [f.name for f in floors]
    try:
        return LiftCar(
            name=_str(doc, "name", f"{key}.name"), shaft=shaft,
            floors=tuple(sorted((str(f) for f in served), key=order.index)),
            outside=outside, inside=inside, waiting=waiting,
            speed=_num(doc, "speed", key, default=1.0),
            floor_height=_num(doc, "floor_height", key, default=3.5),
            door_time=_num(doc, "door_time", key, default=2.5), capacity=capacity)
    except InvalidRequest as exc:
        raise WorldFormatError(f"{key}.{exc.field}", exc.reason) from None


def _door(raw: object, floors: tuple[WorldFloor, ...], key: str) -> WorldDoor:
    """A ``doors:`` entry: ``name``, ``floor``, its place (a segment ``x1, y1, x2, y2`` or
    ``x, y, theta, width``), and optionally ``kind``, ``open_time``, ``close_time``,
    ``controller``."""
    doc = _mapping(raw, key)
    name = _str(doc, "name", f"{key}.name")
    floor = doc.get("floor")
    if floor is None:
        raise WorldFormatError(f"{key}.floor", f"door {name!r} is on no floor")
    names = [f.name for f in floors]
    if floor not in names:
        raise WorldFormatError(f"{key}.floor", f"door {name!r}: no floor {floor!r} "
                                               f"(floors: {names})")
    kind_value = doc.get("kind", DoorKind.DOOR.value)
    try:
        kind = DoorKind(kind_value)
    except ValueError:
        raise WorldFormatError(f"{key}.kind", f"{kind_value!r} is not one of door, gate"
                               ) from None
    controller = doc.get("controller", "simulated")
    if not isinstance(controller, str):
        raise WorldFormatError(f"{key}.controller", f"expected a name, got {controller!r}")
    timing = {"open_time": _num(doc, "open_time", key, default=2.0),
              "close_time": _num(doc, "close_time", key, default=2.0)}
    try:
        if "x1" in doc:
            return WorldDoor(name, floor, _num(doc, "x1", key), _num(doc, "y1", key),
                             _num(doc, "x2", key), _num(doc, "y2", key), kind=kind,
                             controller=controller, **timing)
        return WorldDoor.across(name, floor, _num(doc, "x", key), _num(doc, "y", key),
                                _num(doc, "theta", key, default=0.0), _num(doc, "width", key),
                                kind=kind, controller=controller, **timing)
    except InvalidRequest as exc:
        raise WorldFormatError(f"{key}.{exc.field}", exc.reason) from None


def _cart(raw: object, floors: tuple[WorldFloor, ...], key: str) -> WorldCart:
    """A ``carts:`` entry: ``name``, ``kind`` (cart or cabin), ``floor``, ``x, y, theta``, and
    optionally ``length``, ``width``, ``mass``, ``leg_radius``; a cabin's ``cabin_id``."""
    doc = _mapping(raw, key)
    name = _str(doc, "name", f"{key}.name")
    kind_value = doc.get("kind", CartKind.CART.value)
    try:
        kind = CartKind(kind_value)
    except ValueError:
        raise WorldFormatError(f"{key}.kind", f"{kind_value!r} is not one of cart, cabin"
                               ) from None
    floor = doc.get("floor")
    names = [f.name for f in floors]
    if floor is None:
        raise WorldFormatError(f"{key}.floor", f"{kind.value} {name!r} is on no floor")
    if floor not in names:
        raise WorldFormatError(f"{key}.floor", f"{kind.value} {name!r}: no floor {floor!r} "
                                               f"(floors: {names})")
    cabin_id = doc.get("cabin_id")
    if cabin_id is not None and not isinstance(cabin_id, str):
        raise WorldFormatError(f"{key}.cabin_id", f"expected a string, got {cabin_id!r}")
    pose = _pose(doc, key)
    size = {field: _num(doc, field, key, default=default) for field, default in (
        ("length", 0.9), ("width", 0.7), ("mass", 40.0), ("leg_radius", 0.03))}
    try:
        return WorldCart(name, kind, floor, pose, cabin_id=cabin_id, **size)
    except InvalidRequest as exc:
        raise WorldFormatError(f"{key}.{exc.field}", exc.reason) from None


def _point(raw: object, map_name: str, key: str) -> Point:
    doc = _mapping(raw, key)
    kind_value = doc.get("kind", PointKind.GENERAL.value)
    try:
        kind = PointKind(kind_value)
    except ValueError:
        kinds = ", ".join(k.value for k in PointKind)
        raise WorldFormatError(f"{key}.kind", f"{kind_value!r} is not one of {kinds}") from None
    number = doc.get("number")
    if number is not None and (isinstance(number, bool) or not isinstance(number, int)):
        raise WorldFormatError(f"{key}.number", f"expected an integer, got {number!r}")
    return Point(
        name=_str(doc, "name", f"{key}.name"),
        map_name=map_name,
        pose=_pose(doc, key),
        kind=kind,
        number=number,
    )


def _person(raw: object, key: str) -> PersonRoute:
    doc = _mapping(raw, key)
    waypoints = []
    for n, wp in enumerate(_list(doc.get("waypoints"), f"{key}.waypoints")):
        if not isinstance(wp, list) or len(wp) != 2:
            raise WorldFormatError(f"{key}.waypoints[{n}]", f"expected [x, y], got {wp!r}")
        waypoints.append((_as_num(wp[0], f"{key}.waypoints[{n}]"),
                          _as_num(wp[1], f"{key}.waypoints[{n}]")))
    loop = doc.get("loop", True)
    if not isinstance(loop, bool):
        raise WorldFormatError(f"{key}.loop", f"expected true or false, got {loop!r}")
    try:
        return PersonRoute(
            waypoints=tuple(waypoints),
            speed=_num(doc, "speed", key),
            radius=_num(doc, "radius", key, default=0.25),
            loop=loop,
        )
    except InvalidRequest as exc:
        raise WorldFormatError(f"{key}.{exc.field}", exc.reason) from None


def _pose(doc: dict[str, Any], key: str) -> Pose2D:
    return Pose2D(_num(doc, "x", key), _num(doc, "y", key), _num(doc, "theta", key, default=0.0))


def _mapping(value: object, key: str) -> dict[str, Any]:
    if not isinstance(value, dict):
        raise WorldFormatError(key, f"expected a mapping, got {value!r}")
    return value


def _list(value: object, key: str) -> list[Any]:
    if not isinstance(value, list):
        raise WorldFormatError(key, f"expected a list, got {value!r}")
    return value


def _str(doc: dict[str, Any], field: str, key: str) -> str:
    value = doc.get(field)
    if not isinstance(value, str) or not value:
        raise WorldFormatError(key, f"expected a non-empty string, got {value!r}")
    return value


def _num(doc: dict[str, Any], field: str, key: str, default: float | None = None) -> float:
    if field not in doc:
        if default is None:
            raise WorldFormatError(f"{key}.{field}", "missing")
        return default
    return _as_num(doc[field], f"{key}.{field}")


def _as_num(value: object, key: str) -> float:
    # bool is an int subclass, and "x: yes" is surely a mistake.
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise WorldFormatError(key, f"expected a finite number, got {value!r}")
    return float(value)
