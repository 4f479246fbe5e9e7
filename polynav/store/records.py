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


@dataclass(frozen=True, slots=True)
class TaskRecord:
    """A task as stored: enough to rebuild it (:func:`polynav.tasks.tree.build`) and to say
    how it last stood.

    Attributes:
        id: the task's id.
        name: its name.
        owner: the dialect or service that made it (``native``, ``galileo``...).
        kind: the owner's kind of task (``task``, ``loop``...).
        spec: the tree's JSON form as it was given.
        blackboard: the blackboard's starting values.
        state: the root's last state, in the vendor spelling (``WAITTING`` ... ``FAIL``).
        note: why it ended as it did, when the tree does not say.
        updated: when it last changed (ISO date-time on the robot's calendar).
    """

    id: str
    name: str
    owner: str
    kind: str
    spec: Any
    blackboard: Any
    state: str
    note: str = ""
    updated: str = ""


@dataclass(frozen=True, slots=True)
class ScheduleRecord:
    """A schedule as stored (its meaning is :mod:`polynav.tasks.schedule`'s).

    Attributes:
        id: the schedule's id.
        task_id: the stored task it starts.
        spec: its JSON form (mode, at, times, weekdays, days, loop).
        enabled: whether it starts anything.
        starts: how many times it has started the task.
        next_fire: ISO date-time of its next due start; ``None`` when it has none left.
        updated: when it last changed (ISO date-time on the robot's calendar).
    """

    id: str
    task_id: str
    spec: Any
    enabled: bool = True
    starts: int = 0
    next_fire: str | None = None
    updated: str = ""


@dataclass(frozen=True, slots=True)
class AutomationRecord:
    """An automation task (Galileo's ``blockly_task``): a Python program and its Blockly XML.

    Attributes:
        id: its id.
        title: its title.
        description: what it is for.
        py: the program's source.
        blocklyxml: the Blockly workspace it was generated from.
        is_enabled: whether it may run.
        api_key: the key it calls the robot's API with, if one was given.
        created: when it was made [s since the Unix epoch, as the dialect gave it].
    """

    id: str
    title: str
    description: str
    py: str
    blocklyxml: str
    is_enabled: bool
    api_key: str | None
    created: float
