"""The simulated world: a building of floors, each with its ground-truth map, points and walkers.

A :class:`World` is what the simulator treats as reality. Each :class:`WorldFloor` holds the
ground-truth occupancy :class:`~polynav.maps.map.Map` (the lidar casts its rays into it and the
robot collides with it), the floor's named :class:`~polynav.site.Point` s, the lift shaft that
joins the floors, and the routes the floor's people walk. The world's :class:`LiftCar` s say which
floors each car serves, where its points are and how fast it moves; its :class:`WorldDoor` s are
the electronic doors and gates robots open on their way; its :class:`WorldCart` s the carts and
cabins robots carry (:mod:`polynav.worlds.carts`). The same map also serves as the
navigation map of the demo site, as if it had been surveyed perfectly.
"""

from __future__ import annotations

import enum
import logging
import math
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any, Protocol, TypeVar

from polynav.errors import InvalidRequest
from polynav.geometry import Pose2D
from polynav.maps.map import Map
from polynav.robot.profile import RobotProfile
from polynav.site import Point
from polynav.worlds.carts import WorldCart

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True)
class PersonRoute:
    """The way one person walks, over and over, on one floor.

    Attributes:
        waypoints: corners of the route [m], world frame; at least two.
        speed: walking speed [m/s].
        radius: the person's footprint as a circle [m].
        loop: after the last waypoint walk back to the first (a circuit); if False, turn round
            and walk the route backwards (back and forth).
    """

    waypoints: tuple[tuple[float, float], ...]
    speed: float
    radius: float = 0.25
    loop: bool = True

    def __post_init__(self) -> None:
        if len(self.waypoints) < 2:
            raise InvalidRequest("waypoints", "a person route needs at least two waypoints")
        if not self.speed > 0.0:
            raise InvalidRequest("speed", f"must be > 0, got {self.speed}")
        if not self.radius > 0.0:
            raise InvalidRequest("radius", f"must be > 0, got {self.radius}")


@dataclass(frozen=True, slots=True)
class NoEntrySign:
    """A "no entry" sign standing on a floor (a stand in a doorway, a board across a corridor),
    for a simulated sign camera: seen from the side it faces, within the camera's reach.

    Attributes:
        x, y: where it stands [m], world frame.
        theta: the way its face looks [rad]: it is seen from within 90 degrees of that way.
    """

    x: float
    y: float
    theta: float = 0.0

    def __post_init__(self) -> None:
        if not all(math.isfinite(v) for v in (self.x, self.y, self.theta)):
            raise InvalidRequest("sign", f"x, y, theta must be finite, got {self.x}, {self.y}, "
                                         f"{self.theta}")


@dataclass(frozen=True, slots=True)
class AccessPoint:
    """A Wi-Fi access point on a floor, for the simulated wireless card.

    Attributes:
        ssid: the network name.
        x, y: where it hangs [m], world frame.
        frequency: channel centre [MHz] (2412..2484 for 2.4 GHz, 5170..5825 for 5 GHz).
        security: ``"WPA2"``, ``"WPA WPA2"``... or ``""`` for an open network.
        password: what connecting takes (``""`` for an open network).
    """

    ssid: str
    x: float
    y: float
    frequency: int = 2412
    security: str = "WPA2"
    password: str = ""

    def __post_init__(self) -> None:
        if not self.ssid:
            raise InvalidRequest("ssid", "must not be empty")
        if not (2400 <= self.frequency <= 2500 or 4900 <= self.frequency <= 5900):
            raise InvalidRequest(
                "frequency", f"must be a 2.4 or 5 GHz channel [MHz], got {self.frequency}"
            )
        if bool(self.security) != bool(self.password):
            raise InvalidRequest("password", "a secured network has a password, an open one none")


@dataclass(frozen=True, slots=True)
class LiftShaft:
    """The lift car's floor area on one floor: an axis-aligned rectangle in world metres.

    Every floor of a building has its shaft at the same place, which is what lets a lift ride be
    a change of floor at an unchanged pose.

    Attributes:
        x, y: centre of the car [m].
        width: extent along world x [m].
        depth: extent along world y [m].
        door_heading: direction [rad] from the car's centre out through its door.
        door_width: clear width of the door opening [m].
    """

    x: float
    y: float
    width: float
    depth: float
    door_heading: float = 0.0
    door_width: float = 1.2

    def contains(self, x: float, y: float) -> bool:
        """True if world point (x, y) [m] lies on the car's floor."""
        return abs(x - self.x) <= 0.5 * self.width and abs(y - self.y) <= 0.5 * self.depth

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """(x_min, y_min, x_max, y_max) [m]."""
        hw, hd = 0.5 * self.width, 0.5 * self.depth
        return (self.x - hw, self.y - hd, self.x + hw, self.y + hd)


@dataclass(frozen=True, slots=True)
class LiftCar:
    """One lift car of the building: its shaft, the floors it serves and how it moves.

    The car's shaft is at the same place on every floor it serves (a ride changes the floor, not
    the pose), and each of those floors has the car's ``outside`` and ``inside`` points.

    Attributes:
        name: the car's id (``"lift_1"``); the lease book's resource is ``lift:<name>``.
        shaft: the car's floor area.
        floors: names of the floors the car stops at, in the world's floor order.
        outside: name of the point in front of the door, on each served floor.
        inside: name of the point in the car, on each served floor.
        waiting: where a robot waits for the car's session [m] (off the door's path), or
            ``None`` to wait at the outside point.
        speed: travel speed between floors [m/s].
        floor_height: storey height [m]; a ride of n levels takes n * floor_height / speed.
        door_time: how long the doors take to open or to close [s].
        capacity: how many riders (robots and people) fit.
    """

    name: str
    shaft: LiftShaft
    floors: tuple[str, ...]
    outside: str
    inside: str
    waiting: tuple[float, float] | None = None
    speed: float = 1.0
    floor_height: float = 3.5
    door_time: float = 2.5
    capacity: int = 1

    def __post_init__(self) -> None:
        if not self.name:
            raise InvalidRequest("name", "a lift car needs a name")
        if len(self.floors) < 2 or len(set(self.floors)) != len(self.floors):
            raise InvalidRequest("floors", f"a lift serves at least two distinct floors, got "
                                           f"{list(self.floors)}")
        for key in ("speed", "floor_height", "door_time"):
            if not getattr(self, key) > 0.0:
                raise InvalidRequest(key, f"must be > 0, got {getattr(self, key)}")
        if self.capacity < 1:
            raise InvalidRequest("capacity", f"must be at least 1, got {self.capacity}")


class DoorKind(enum.Enum):
    """What closes a passage: a hinged or sliding ``door``, or a ``gate`` (a turnstile or a
    barrier across a lobby). Both open and close alike; the kind is for people and dialects."""

    DOOR = "door"
    GATE = "gate"


DOOR_CONTROLLERS = ("simulated",)
"""Controllers a world file may name for a door: the simulator's (a real site's controllers
go behind :class:`polynav.robot.door.Door` in its own backend)."""


@dataclass(frozen=True, slots=True)
class WorldDoor:
    """An electronic door or gate on one floor: a segment the robot crosses, closed by a leaf.

    Closed, its leaf stands on the segment (the lidar sees it, a body collides with it); open,
    the passage is free. Routes may cross it: the robot opens it on the way (see
    :mod:`polynav.runtime.door_passage`).

    Attributes:
        name: the door's id; the lease book's resource is ``door:<name>``.
        floor: the floor it is on.
        x1, y1, x2, y2: the ends of the leaf's segment [m], world frame.
        kind: door or gate.
        open_time: how long it takes to open [s].
        close_time: how long it takes to close [s].
        controller: what drives it (``simulated``).
    """

    name: str
    floor: str
    x1: float
    y1: float
    x2: float
    y2: float
    kind: DoorKind = DoorKind.DOOR
    open_time: float = 2.0
    close_time: float = 2.0
    controller: str = "simulated"

    def __post_init__(self) -> None:
        if not self.name:
            raise InvalidRequest("name", "a door needs a name")
        if not self.floor:
            raise InvalidRequest("floor", f"door {self.name!r} is on no floor")
        if not self.width > 0.0:
            raise InvalidRequest("width", f"door {self.name!r}: must be > 0, got {self.width}")
        for key in ("open_time", "close_time"):
            if not getattr(self, key) > 0.0:
                raise InvalidRequest(key, f"must be > 0, got {getattr(self, key)}")
        if self.controller not in DOOR_CONTROLLERS:
            raise InvalidRequest("controller", f"{self.controller!r} is not one of "
                                               f"{', '.join(DOOR_CONTROLLERS)}")

    @classmethod
    def across(cls, name: str, floor: str, x: float, y: float, theta: float, width: float,
               **kwargs: Any) -> WorldDoor:
        """The door whose centre is at (x, y) and which is crossed heading ``theta`` [rad]:
        its segment, ``width`` long, stands across that heading.

        Raises:
            InvalidRequest: ``width`` is not > 0 (or another field is invalid).
        """
        if not width > 0.0:
            raise InvalidRequest("width", f"door {name!r}: must be > 0, got {width}")
        dx, dy = -math.sin(theta) * width / 2.0, math.cos(theta) * width / 2.0
        return cls(name, floor, x - dx, y - dy, x + dx, y + dy, **kwargs)

    @property
    def width(self) -> float:
        """The clear width of the passage [m]."""
        return math.hypot(self.x2 - self.x1, self.y2 - self.y1)

    @property
    def centre(self) -> tuple[float, float]:
        return (0.5 * (self.x1 + self.x2), 0.5 * (self.y1 + self.y2))

    def distance_to(self, x: float, y: float) -> float:
        """Distance [m] from world point (x, y) to the leaf's segment."""
        ex, ey = self.x2 - self.x1, self.y2 - self.y1
        t = ((x - self.x1) * ex + (y - self.y1) * ey) / (ex * ex + ey * ey)
        t = min(1.0, max(0.0, t))
        return math.hypot(x - (self.x1 + t * ex), y - (self.y1 + t * ey))

    def crossing_flow(self, x: float, y: float) -> str:
        """The compass sector (``E``, ``N``, ``W``, ``S``) a robot at (x, y) crosses the leaf
        heading: away from its side. A lease named with it is shared with robots crossing the
        same way (:mod:`polynav.leases.book`): robots following one another through a door go
        together, and the other way waits until they are through. The two ways through a leaf
        always fall in opposite sectors, whatever its angle."""
        ex, ey = self.x2 - self.x1, self.y2 - self.y1
        cx, cy = self.centre
        # The leaf's normal on the far side from (x, y).
        side = ex * (y - cy) - ey * (x - cx)
        nx, ny = (ey, -ex) if side >= 0.0 else (-ey, ex)
        return "ENWS"[round(math.atan2(ny, nx) / (math.pi / 2.0)) % 4]


@dataclass(frozen=True, slots=True, eq=False)
class WorldFloor:
    """One floor of the world: ground truth, named points, lift shaft and walkers.

    Attributes:
        name: the floor's name (``"floor1"``).
        level: storey number, for ordering and lift buttons.
        map_name: the name of the navigation map of this floor (points refer to it).
        map: ground-truth occupancy.
        points: the floor's named points.
        lift: the lift car's area on this floor, if a lift stops here.
        people: routes of the people walking on this floor.
        access_points: the Wi-Fi access points on this floor.
        signs: the "no entry" signs standing on this floor.
    """

    name: str
    level: int
    map_name: str
    map: Map
    points: tuple[Point, ...]
    lift: LiftShaft | None
    people: tuple[PersonRoute, ...]
    access_points: tuple[AccessPoint, ...] = ()
    signs: tuple[NoEntrySign, ...] = ()

    def point(self, name: str) -> Point:
        """The point called ``name`` on this floor.

        Raises:
            InvalidRequest: no point has that name.
        """
        return _named(self.points, name, "point", f"on floor {self.name!r}")


@dataclass(frozen=True, slots=True, eq=False)
class World:
    """A whole simulated building, and where the robot starts in it."""

    name: str
    floors: tuple[WorldFloor, ...]
    start_floor: str
    start_pose: Pose2D
    robot: RobotProfile | None = None
    """The robot the world is for (``robot:`` in world.yaml); ``None``: whichever is given."""
    lifts: tuple[LiftCar, ...] = ()
    """The building's lift cars (``lifts:`` in world.yaml)."""
    doors: tuple[WorldDoor, ...] = ()
    """The building's electronic doors and gates (``doors:`` in world.yaml)."""
    carts: tuple[WorldCart, ...] = ()
    """The carts and cabins standing in the building (``carts:`` in world.yaml)."""

    def cart(self, name: str) -> WorldCart:
        """The cart or cabin called ``name``.

        Raises:
            InvalidRequest: none has that name.
        """
        return _named(self.carts, name, "cart", f"in world {self.name!r}")

    def door(self, name: str) -> WorldDoor:
        """The door called ``name``.

        Raises:
            InvalidRequest: no door has that name.
        """
        return _named(self.doors, name, "door", f"in world {self.name!r}")

    def lift(self, name: str) -> LiftCar:
        """The lift car called ``name``.

        Raises:
            InvalidRequest: no car has that name.
        """
        return _named(self.lifts, name, "lift", f"in world {self.name!r}")

    def floor(self, name: str) -> WorldFloor:
        """The floor called ``name``.

        Raises:
            InvalidRequest: no floor has that name.
        """
        return _named(self.floors, name, "floor", f"in world {self.name!r}")


class _Named(Protocol):
    @property
    def name(self) -> str: ...


_N = TypeVar("_N", bound=_Named)


def _named(items: Iterable[_N], name: str, kind: str, where: str) -> _N:
    """The item called ``name``; a client's unknown name is its own error, not a KeyError."""
    for item in items:
        if item.name == name:
            return item
    raise InvalidRequest(kind, f"no {kind} {name!r} {where}")
