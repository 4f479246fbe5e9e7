"""Goals on another map: the actions that take the robot across the site's direct connections.

A Galileo goal names a (map, path, index) or a pose on a map; when the map is not the one in
use, the robot goes to a connection point, switches maps there and goes on (galileo-http-b
§1.6). The site's direct connections (the store's ``{"type": "direct", "from", "to"}`` records,
which Galileo ``point_connections`` creates) are searched breadth-first, so the chain with the
fewest map switches wins (the document names no weights). Each crossing is a ``nav_action`` to
the exit point and a ``switch_map_action`` that starts navigation on the next map at the entry
point (on the simulator the robot is carried there, as an operator would carry it; a direct
connection says the two points are the same place). A map no direct connection reaches is
left to the runtime: the goal goes to ``runtime.go_to`` with its map, and the runtime's
multi-map router (:mod:`polynav.routing.router`) takes it across the site's lifts (and direct
connections), or refuses it with its reason (``NoRoute``, a 409).
"""

from __future__ import annotations

import logging
from collections import deque
from dataclasses import dataclass

from polynav.errors import Conflict, NotFound
from polynav.protocols.galileo import session as sessions
from polynav.protocols.galileo.actions import Action, NavAction, SwitchMapAction
from polynav.protocols.galileo.context import TARGET_WITHOUT_ID, Context, Target

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True)
class Crossing:
    """One direct connection taken from ``from_map``'s point to ``to_map``'s."""

    from_map: str
    from_point: str
    to_map: str
    to_point: str


def map_of_level(ctx: Context, level: int) -> str:
    """The map of the floor at ``level``.

    Raises:
        NotFound: no floor has that level.
    """
    for floor in ctx.store.floors():
        if floor.level == level:
            return floor.map_name
    raise NotFound("floor of level", str(level))


def _edges(ctx: Context) -> dict[str, list[Crossing]]:
    out: dict[str, list[Crossing]] = {}
    for record in ctx.store.connections():
        data = record.data
        if not isinstance(data, dict) or data.get("type") != "direct":
            continue
        a, b = data.get("from"), data.get("to")
        if not (isinstance(a, dict) and isinstance(b, dict)):
            continue
        try:
            ends = (str(a["map"]), str(a["point"]), str(b["map"]), str(b["point"]))
        except KeyError:
            continue
        out.setdefault(ends[0], []).append(Crossing(*ends))
        out.setdefault(ends[2], []).append(Crossing(ends[2], ends[3], ends[0], ends[1]))
    return out


def route(ctx: Context, from_map: str, to_map: str) -> list[Crossing]:
    """The crossings from ``from_map`` to ``to_map`` with the fewest map switches.

    Raises:
        Conflict: no chain of direct connections joins them.
    """
    edges = _edges(ctx)
    previous: dict[str, Crossing | None] = {from_map: None}
    queue = deque([from_map])
    while queue:
        here = queue.popleft()
        if here == to_map:
            break
        for crossing in edges.get(here, []):
            if crossing.to_map not in previous:
                previous[crossing.to_map] = crossing
                queue.append(crossing.to_map)
    if to_map not in previous:
        raise Conflict(f"no connection leads from map {from_map!r} to map {to_map!r}")
    chain: list[Crossing] = []
    step = previous[to_map]
    while step is not None:
        chain.append(step)
        step = previous[step.from_map]
    return chain[::-1]


def actions_between(ctx: Context, from_map: str, to_map: str) -> list[Action]:
    """The actions that bring the robot from ``from_map`` onto ``to_map``, entry point first.

    Raises:
        Conflict: no chain of direct connections joins the two maps.
        NotFound: a connection's point was deleted since.
    """
    actions: list[Action] = []
    unnamed = Target(TARGET_WITHOUT_ID)
    for crossing in route(ctx, from_map, to_map):
        exit_point = ctx.store.point(crossing.from_map, crossing.from_point)
        entry = ctx.store.point(crossing.to_map, crossing.to_point)
        actions.append(NavAction(pose=exit_point.pose, point=exit_point.name,
                                 map_name=crossing.from_map,
                                 on_attempt=lambda a: ctx.remember_target(a, unnamed)))
        path = sessions.current_path(ctx, crossing.to_map)
        index = _index(ctx, crossing.to_map, path, entry.name)
        actions.append(SwitchMapAction(map_name=crossing.to_map, path=path,
                                       start_index=index, point=entry.name))
    return actions


def _index(ctx: Context, map_name: str, path: str, point: str) -> int:
    try:
        stops = sessions.routes(ctx).route(map_name, path).stops
    except NotFound:
        return -1
    for i, stop in enumerate(stops):
        if stop.point == point:
            return i
    return -1
