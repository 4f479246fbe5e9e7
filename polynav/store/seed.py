"""What a fresh data directory starts with: a site copied from a simulated world.

The demo world is both the simulator's reality and a perfectly surveyed site, so its floors,
navigation maps and named points (including the lift points beside its shafts) become the
store's first content, and each lift car becomes a ``lift`` connection (see
:func:`lift_connection`). :func:`seed_plan` only translates; the store writes the plan in one
transaction (:meth:`~polynav.store.site_store.SiteStore.open`), so a crash while seeding leaves
an empty store that seeds again on the next start.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

from polynav.maps.map import Map
from polynav.site import Point
from polynav.store.records import ConnectionRecord, FloorRecord
from polynav.worlds.world import LiftCar, World

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True, eq=False)
class SeedMap:
    """A map to write while seeding: its name, its floor and the grid."""

    name: str
    floor: str | None
    grid: Map


@dataclass(frozen=True, slots=True, eq=False)
class SeedPlan:
    """Everything a fresh store receives, in store terms.

    Attributes:
        source: the world's name, recorded in the store as where its data came from.
        floors: one record per floor.
        maps: one map per floor, named as the floor's ``map_name``.
        points: every floor's points, in the world's order.
        connections: one ``lift`` connection per lift car.
    """

    source: str
    floors: tuple[FloorRecord, ...]
    maps: tuple[SeedMap, ...]
    points: tuple[Point, ...]
    connections: tuple[ConnectionRecord, ...] = ()


def lift_connection(world: World, car: LiftCar) -> ConnectionRecord:
    """The store's record of a lift car (the shape :mod:`polynav.routing.connections` reads)::

        {"type": "lift", "car": "lift_1",
         "stops": [{"floor": "floor1", "map": "floor1", "outside": "lift_1_outside",
                    "inside": "lift_1_inside", "waiting": {"x": 38.9, "y": 15.6}}, ...]}
    """
    stops: list[dict[str, object]] = []
    for name in car.floors:
        floor = world.floor(name)
        stop: dict[str, object] = {"floor": floor.name, "map": floor.map_name,
                                   "outside": car.outside, "inside": car.inside}
        if car.waiting is not None:
            stop["waiting"] = {"x": car.waiting[0], "y": car.waiting[1]}
        stops.append(stop)
    return ConnectionRecord(car.name, {"type": "lift", "car": car.name, "stops": stops})


def seed_plan(world: World) -> SeedPlan:
    """Translate ``world`` into the floors, maps, points and connections of a new site."""
    floors = tuple(FloorRecord(f.name, f.level, f.map_name) for f in world.floors)
    maps = tuple(SeedMap(f.map_name, f.name, f.map) for f in world.floors)
    points = tuple(p for f in world.floors for p in f.points)
    connections = tuple(lift_connection(world, car) for car in world.lifts)
    return SeedPlan(world.name, floors, maps, points, connections)
