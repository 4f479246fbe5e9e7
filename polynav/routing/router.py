"""The multi-map router: a graph over maps and connection points, searched for the quickest route.

Nodes are the start, the goal, each lift car's outside point on each floor it serves, and both
ends of each direct connection. Edges, weighed in expected seconds:

- **in a map**, between any two nodes on the same map: the length of the path the real planner
  plans on that map's stored map and keepouts (:class:`PathCosts`, cached by the caller and
  invalidated when the map or its keepouts change), over ``drive_speed``;
- **a lift ride**, between two stops of one car: the car's expected arrival at the first floor
  (from its state now), the ride (:meth:`~polynav.robot.lift.Lift.travel_time`), a fixed
  overhead for driving in and out, and a penalty while another robot holds the car's session;
- **a direct connection**: a fixed switch time.

Dijkstra over this graph (a handful of nodes; each in-map edge is planned only when the search
reaches it) gives the legs. When there is no route the reason is told apart (DESIGN §4): no lift
serves the start or goal floor, the cars that would serve are out of service (or were excluded
after failing, e.g. full), or the goal is unreachable on its map from every lift.
"""

from __future__ import annotations

import heapq
import logging
import math
from collections.abc import Collection, Mapping
from dataclasses import dataclass, field
from typing import Protocol

from polynav.errors import ConfigError, NotFound
from polynav.geometry import Pose2D
from polynav.planning.errors import PlanningError
from polynav.robot.lift import Lift, LiftMode
from polynav.routing.connections import Connections, DirectConnection, LiftStop
from polynav.routing.errors import NoRoute, NoRouteReason
from polynav.routing.route import DriveLeg, Leg, LiftLeg, Route, SwitchLeg
from polynav.site import Point

log = logging.getLogger(__name__)


class PathCosts(Protocol):
    """Planned path lengths on the site's maps."""

    def length(self, map_name: str, start: Pose2D, goal: Pose2D) -> float:
        """Length [m] of the planned path; raises PlanningError when there is none."""
        ...


class PointLookup(Protocol):
    """The part of the site store the router reads."""

    def point(self, map_name: str, name: str) -> Point: ...


@dataclass(frozen=True, slots=True)
class RouterConfig:
    """Weights of the route search.

    Attributes:
        drive_speed: the speed [m/s] in-map path lengths are divided by.
        lift_overhead: driving into and out of a car [s], on top of the car's own times.
        busy_penalty: added [s] to a car whose session another robot holds.
        switch_time: changing maps at a direct connection [s].
    """

    drive_speed: float = 0.5
    lift_overhead: float = 20.0
    busy_penalty: float = 60.0
    switch_time: float = 5.0

    def __post_init__(self) -> None:
        for key in ("drive_speed", "lift_overhead", "busy_penalty", "switch_time"):
            value = getattr(self, key)
            if not (math.isfinite(value) and value >= 0.0) or (
                    key == "drive_speed" and value == 0.0):
                raise ConfigError(f"routing.{key}", f"must be finite and > 0, got {value}")


@dataclass(frozen=True, slots=True)
class _Node:
    map_name: str
    pose: Pose2D
    label: str
    car: str | None = None
    stop: LiftStop | None = None
    direct: DirectConnection | None = None
    direct_end: int = 0


@dataclass(slots=True)
class _Search:
    nodes: list[_Node]
    unreachable: list[str] = field(default_factory=list)


class Router:
    """Routes across maps (see the module docstring).

    Args:
        points: the site's points (connection points are looked up by name).
        costs: planned path lengths.
        config: the weights.
    """

    def __init__(self, points: PointLookup, costs: PathCosts,
                 config: RouterConfig | None = None) -> None:
        self._points = points
        self._costs = costs
        self.config = config or RouterConfig()

    def route(
        self,
        connections: Connections,
        lifts: Mapping[str, Lift],
        *,
        start_map: str,
        start: Pose2D,
        goal_map: str,
        goal: Pose2D,
        goal_point: str | None = None,
        exclude: Collection[str] = (),
        holder: str = "",
    ) -> Route:
        """The quickest route from ``start`` on ``start_map`` to ``goal`` on ``goal_map``.

        Args:
            connections: the site's connections.
            lifts: the cars by name (their state weighs the wait; a car without an entry is
                out of service).
            exclude: cars not to use (they failed this robot already: full, blocked).
            holder: the robot asking (a session it holds is no penalty).

        Raises:
            NoRoute: no route, with the reason.
        """
        if start_map == goal_map:
            length = self._drive(start_map, start, goal)
            if math.isinf(length):
                raise NoRoute(NoRouteReason.UNREACHABLE,
                              f"{goal_point or 'the goal'} cannot be reached on map {goal_map!r}")
            return Route((DriveLeg(goal_map, goal, goal_point),), length)
        served = {s.map_name for lift in connections.lifts for s in lift.stops} | {
            m for d in connections.directs for m in (d.from_map, d.to_map)}
        for map_name in (start_map, goal_map):
            if map_name not in served:
                raise NoRoute(NoRouteReason.NO_LIFT,
                              f"no lift or connection serves map {map_name!r}")
        usable = {car for car, lift in lifts.items()
                  if car not in exclude and lift.state().mode is LiftMode.NORMAL}
        nodes = self._nodes(connections, start_map, start, goal_map, goal)
        search = _Search(nodes)
        found = self._search(search, lifts, usable, holder)
        if found is not None:
            return self._legs(found[0], nodes, goal_point, found[1])
        every = {lift.car for lift in connections.lifts}
        if every - usable and self._search(_Search(nodes), lifts, every, holder,
                                           weigh_lifts=False) is not None:
            down = sorted(c for c in every - usable if c not in exclude)
            excluded = sorted(c for c in every - usable if c in exclude)
            parts = []
            if down:
                parts.append(f"out of service: {', '.join(down)}")
            if excluded:
                parts.append(f"already failed: {', '.join(excluded)}")
            raise NoRoute(NoRouteReason.OUT_OF_SERVICE,
                          f"the lifts from {start_map!r} to {goal_map!r} are unavailable ("
                          + "; ".join(parts) + ")")
        if search.unreachable:
            raise NoRoute(NoRouteReason.UNREACHABLE,
                          f"{goal_point or 'the goal'} on map {goal_map!r}: no path between "
                          + ", ".join(sorted(set(search.unreachable))))
        raise NoRoute(NoRouteReason.NO_LIFT,
                      f"no lift joins map {start_map!r} and map {goal_map!r}")

    # -- the graph -----------------------------------------------------------------------------

    def _nodes(self, connections: Connections, start_map: str, start: Pose2D, goal_map: str,
               goal: Pose2D) -> list[_Node]:
        nodes = [_Node(start_map, start, "start"), _Node(goal_map, goal, "goal")]
        for lift in connections.lifts:
            for stop in lift.stops:
                try:
                    pose = self._points.point(stop.map_name, stop.outside).pose
                except NotFound:
                    log.warning("lift %s: no point %s on %s; stop skipped", lift.car,
                                stop.outside, stop.map_name)
                    continue
                nodes.append(_Node(stop.map_name, pose, f"{lift.car}@{stop.floor}",
                                   car=lift.car, stop=stop))
        for d in connections.directs:
            try:
                a = self._points.point(d.from_map, d.from_point).pose
                b = self._points.point(d.to_map, d.to_point).pose
            except NotFound:
                log.warning("connection %s names a point that is gone; skipped", d.name)
                continue
            nodes.append(_Node(d.from_map, a, f"{d.from_map}/{d.from_point}", direct=d))
            nodes.append(_Node(d.to_map, b, f"{d.to_map}/{d.to_point}", direct=d, direct_end=1))
        return nodes

    def _search(self, search: _Search, lifts: Mapping[str, Lift], usable: Collection[str],
                holder: str, *, weigh_lifts: bool = True) -> tuple[list[int], float] | None:
        best = {0: 0.0}
        previous: dict[int, int] = {}
        heap = [(0.0, 0)]
        done: set[int] = set()
        while heap:
            cost, u = heapq.heappop(heap)
            if u in done:
                continue
            done.add(u)
            if u == 1:
                path = [1]
                while path[-1] != 0:
                    path.append(previous[path[-1]])
                return path[::-1], cost
            for v, step in self._edges(search, u, lifts, usable, holder, weigh_lifts):
                total = cost + step
                if total < best.get(v, math.inf):
                    best[v] = total
                    previous[v] = u
                    heapq.heappush(heap, (total, v))
        return None

    def _edges(self, search: _Search, u: int, lifts: Mapping[str, Lift],
               usable: Collection[str], holder: str, weigh_lifts: bool
               ) -> list[tuple[int, float]]:
        nodes = search.nodes
        here = nodes[u]
        out: list[tuple[int, float]] = []
        for v, there in enumerate(nodes):
            if v == u or v == 0 or there.map_name != here.map_name:
                continue
            if here.car is not None and there.car == here.car:
                continue  # one car's stop to itself: a ride, not a drive
            length = self._drive(here.map_name, here.pose, there.pose)
            if math.isinf(length):
                if v == 1 or u == 0:
                    search.unreachable.append(f"{here.label} and {there.label}")
                continue
            out.append((v, length / self.config.drive_speed))
        if here.car is not None and here.car in usable and here.stop is not None:
            for v, there in enumerate(nodes):
                if there.car != here.car or there.stop is None or v == u:
                    continue
                wait = 0.0
                lift = lifts.get(here.car)
                if weigh_lifts and lift is not None:
                    state = lift.state()
                    wait = lift.expected_arrival(here.stop.floor) + lift.travel_time(
                        here.stop.floor, there.stop.floor)
                    if state.session_id and state.session_id != holder:
                        wait += self.config.busy_penalty
                out.append((v, wait + self.config.lift_overhead))
        if here.direct is not None:
            for v, there in enumerate(nodes):
                if there.direct is here.direct and there.direct_end != here.direct_end:
                    out.append((v, self.config.switch_time))
        return out

    def _drive(self, map_name: str, start: Pose2D, goal: Pose2D) -> float:
        try:
            return self._costs.length(map_name, start, goal)
        except PlanningError as exc:
            log.debug("no path on %s from %s to %s: %s", map_name, start, goal, exc)
            return math.inf

    # -- legs ----------------------------------------------------------------------------------

    def _legs(self, path: list[int], nodes: list[_Node], goal_point: str | None,
              cost: float) -> Route:
        legs: list[Leg] = []
        for a, b in zip(path[:-1], path[1:], strict=True):
            here, there = nodes[a], nodes[b]
            if here.map_name == there.map_name and not (
                    here.car is not None and here.car == there.car):
                point = goal_point if b == 1 else (
                    there.stop.outside if there.stop is not None else None)
                legs.append(DriveLeg(there.map_name, there.pose, point))
            elif here.stop is not None and there.stop is not None and here.car is not None:
                legs.append(self._lift_leg(here.car, here.stop, there.stop, here.pose,
                                           there.pose))
            elif here.direct is not None:
                point = there.direct.to_point if there.direct_end == 1 and there.direct else ""
                legs.append(SwitchLeg(here.map_name, there.map_name, here.pose, there.pose,
                                      point))
        return Route(tuple(legs), cost)

    def _lift_leg(self, car: str, a: LiftStop, b: LiftStop, outside_from: Pose2D,
                  outside_to: Pose2D) -> LiftLeg:
        inside_from = self._points.point(a.map_name, a.inside).pose
        inside_to = self._points.point(b.map_name, b.inside).pose
        waiting = None
        if a.waiting is not None:
            # Face the door from the waiting spot, so the robot is ready to drive in.
            waiting = Pose2D(a.waiting[0], a.waiting[1],
                             math.atan2(outside_from.y - a.waiting[1],
                                        outside_from.x - a.waiting[0]))
        return LiftLeg(car=car, from_floor=a.floor, from_map=a.map_name, to_floor=b.floor,
                       to_map=b.map_name, outside_from=outside_from, inside_from=inside_from,
                       outside_to=outside_to, inside_to=inside_to, waiting_from=waiting,
                       outside_point=b.outside, inside_point=a.inside)
