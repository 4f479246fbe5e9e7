"""The Galileo navigation session: the map and path in use, the last start, dispatch mode.

The vendor's robot remembers the map, path and ``start_index`` of the last
``navigation/start`` as the defaults of the next one (galileo-http-b E9), and reports them in
``current_path``/``current_map``. polynav keeps that memory here, per adapter. When nothing was
started yet, the map is the map of the floor the robot stands on and the path is the map's
default path (:data:`~polynav.store.route_stops.DEFAULT_ROUTE`), so a script that starts
navigation with no parameters runs out of the box (issue item 3).
"""

from __future__ import annotations

import logging
import threading
from dataclasses import dataclass, field

from polynav.errors import Conflict, InvalidRequest, NotFound
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.params import Params
from polynav.site import Point, PointKind
from polynav.store.route_stops import DEFAULT_ROUTE, RouteBook

log = logging.getLogger(__name__)

#: ``start_index`` of the charge pile.
CHARGE_PILE = -1


@dataclass
class Session:
    """What the adapter remembers between navigation starts.

    Attributes:
        map_name: the map of the last start (or ``switch_map``), ``None`` before any.
        paths: the path last used on each map.
        start_index: the ``start_index`` of the last start.
        dispatch: the robot is in dispatch (Lagrange "schedule") mode: Galileo goal endpoints
            refuse.
    """

    map_name: str | None = None
    paths: dict[str, str] = field(default_factory=dict)
    start_index: int | None = None
    dispatch: bool = False
    lock: threading.Lock = field(default_factory=threading.Lock)


def session(ctx: Context) -> Session:
    return ctx.state("session", Session)


def routes(ctx: Context) -> RouteBook:
    """The site's routes with stops (the Galileo paths and target points)."""
    return ctx.state("routes", lambda: RouteBook(ctx.store))


def current_map(ctx: Context) -> str:
    """The map in use: navigation's, else the last started or switched to, else the map of
    the robot's floor, else the first map.

    Raises:
        NotFound: the site has no map.
    """
    snap = ctx.runtime.status()
    if snap.map is not None:
        return snap.map
    s = session(ctx)
    if s.map_name is not None:
        return s.map_name
    if snap.floor is not None:
        try:
            return ctx.store.floor(snap.floor).map_name
        except NotFound:
            pass
    maps = ctx.store.maps()
    if not maps:
        raise NotFound("map", "(any)")
    return maps[0].name


def map_of_level(ctx: Context, level: int) -> str:
    """The map of the floor at ``level`` (Galileo's ``level`` parameters name floors).

    Raises:
        NotFound: no floor has that level.
    """
    for floor in ctx.store.floors():
        if floor.level == level:
            return floor.map_name
    raise NotFound("floor of level", str(level))


def current_path(ctx: Context, map_name: str | None = None) -> str:
    """The path in use on ``map_name`` (default: the current map)."""
    name = map_name or current_map(ctx)
    return session(ctx).paths.get(name, DEFAULT_ROUTE)


def charge_pile(ctx: Context, map_name: str) -> Point:
    """The map's charge pile: its first charger point.

    Raises:
        NotFound: the map has no charger point.
    """
    for point in ctx.store.points(map_name=map_name):
        if point.kind is PointKind.CHARGER:
            return point
    raise NotFound("charge pile on map", map_name)


def start_point(
    ctx: Context, params: Params, map_name: str, path: str
) -> tuple[int | None, str | None]:
    """The ``start_index`` of a start request and the name of the target point of (map, path)
    it names (``None`` without one: polynav then finds the robot itself).

    Raises:
        InvalidRequest: a mistyped or out-of-range index.
        NotFound: unknown path, or no charge pile.
    """
    index = params.integer("start_index", None)
    if index is None:
        return None, None
    return index, target_point(ctx, map_name, path, index).name


def target_point(ctx: Context, map_name: str, path: str, index: int) -> Point:
    """The point of target ``index`` of (map, path); ``-1`` is the charge pile.

    Raises:
        NotFound: unknown map, path, or no charge pile.
        InvalidRequest: index out of range.
    """
    if index == CHARGE_PILE:
        routes(ctx).route(map_name, path)  # the path must exist all the same
        return charge_pile(ctx, map_name)
    if index < -1:
        raise InvalidRequest("index", f"must be -1 (charge pile) or a target index, got {index}")
    return routes(ctx).stop_point(map_name, path, index)


def require_goals_allowed(ctx: Context) -> None:
    """Goal endpoints refuse in dispatch mode (A-28) and when not navigating.

    Raises:
        Conflict: dispatch mode, or not navigating.
    """
    if session(ctx).dispatch:
        raise Conflict("the robot is in dispatch (schedule) mode: Galileo goals are refused")
    mode = ctx.runtime.status().mode
    if mode != "navigating":
        raise Conflict(f"navigation is not started (system state {mode}): "
                       "call /api/v1/navigation/start first")
