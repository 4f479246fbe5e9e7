"""Values the site store hands out besides :class:`~polynav.site.Point`: floors, maps, routes.

They are plain frozen records of what is stored, so the layers above (runtime, API, adapters)
never see a database row. Route and connection geometry is kept as JSON-ready data until the
issues that give routes and connections a meaning define their value types.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from polynav.geometry import Pose2D


@dataclass(frozen=True, slots=True)
class FloorRecord:
    """One storey of the site.

    Attributes:
        name: the floor's name (``"floor1"``), unique in the site.
        level: storey number, for ordering and lift buttons.
        map_name: the navigation map of this floor.
    """

    name: str
    level: int
    map_name: str


@dataclass(frozen=True, slots=True)
class MapRecord:
    """What the store knows about a saved map without loading its picture.

    Attributes:
        name: the map's name, unique in the site.
        floor: the floor the map belongs to, if any.
        resolution: cell size [m].
        width: cells along the map's x axis.
        height: cells along the map's y axis.
        origin: world pose of the lower-left corner of cell (0, 0) (ROS map_server).
    """

    name: str
    floor: str | None
    resolution: float
    width: int
    height: int
    origin: Pose2D


@dataclass(frozen=True, slots=True)
class RouteRecord:
    """A named route graph (paths the robot should follow) on one map.

    Attributes:
        name: unique per map.
        map_name: the map the route is drawn on.
        geometry: JSON-ready data (nodes, edges, ...) whose shape a later issue fixes.
    """

    name: str
    map_name: str
    geometry: Any


@dataclass(frozen=True, slots=True)
class ConnectionRecord:
    """A named link between maps (a lift, a door between buildings).

    Attributes:
        name: unique in the site.
        data: JSON-ready data (the maps and points it joins, ...) whose shape a later issue fixes.
    """

    name: str
    data: Any
