"""The site's connections as typed values, read from the store's JSON records.

The store keeps each connection as a named JSON document (``store/records.py``):

- ``{"type": "lift", "car": "lift_1", "stops": [{"floor", "map", "outside", "inside",
  "waiting": {"x", "y"}?}, ...]}``: a car and, per floor it serves, the map and the names of the
  points outside its door and inside it (seeded from the world's ``lifts:``);
- ``{"type": "direct", "from": {"map", "point"}, "to": {"map", "point"}}``: the same place in
  two maps (Galileo ``point_connections`` writes these).

A record of another type, or one missing a field, is skipped with a warning: a connection the
router cannot read must not stop the others from working.
"""

from __future__ import annotations

import logging
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

from polynav.store.records import ConnectionRecord

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True)
class LiftStop:
    """One floor a car serves: the floor's map and the car's points there."""

    floor: str
    map_name: str
    outside: str
    inside: str
    waiting: tuple[float, float] | None = None


@dataclass(frozen=True, slots=True)
class LiftConnection:
    """A car and the floors it serves, lowest first as stored."""

    car: str
    stops: tuple[LiftStop, ...]

    def stop_on(self, map_name: str) -> LiftStop | None:
        """The car's stop on ``map_name``, if it serves it."""
        for stop in self.stops:
            if stop.map_name == map_name:
                return stop
        return None


@dataclass(frozen=True, slots=True)
class DirectConnection:
    """The same place as a point of one map and a point of another."""

    name: str
    from_map: str
    from_point: str
    to_map: str
    to_point: str


@dataclass(frozen=True, slots=True)
class Connections:
    """Everything that joins the site's maps."""

    lifts: tuple[LiftConnection, ...]
    directs: tuple[DirectConnection, ...]

    def lift(self, car: str) -> LiftConnection | None:
        for lift in self.lifts:
            if lift.car == car:
                return lift
        return None


def parse(records: Iterable[ConnectionRecord]) -> Connections:
    """Typed connections from the store's records (malformed ones skipped, see the module)."""
    lifts: list[LiftConnection] = []
    directs: list[DirectConnection] = []
    for record in records:
        data = record.data
        try:
            if not isinstance(data, dict):
                raise TypeError("not an object")
            kind = data.get("type")
            if kind == "lift":
                lifts.append(_lift(record.name, data))
            elif kind == "direct":
                directs.append(_direct(record.name, data))
        except (KeyError, TypeError, ValueError) as exc:
            log.warning("connection %r skipped: %s", record.name, exc)
    return Connections(tuple(lifts), tuple(directs))


def _lift(name: str, data: dict[str, Any]) -> LiftConnection:
    stops = []
    for raw in data["stops"]:
        waiting = raw.get("waiting")
        wait = (float(waiting["x"]), float(waiting["y"])) if isinstance(waiting, dict) else None
        stops.append(LiftStop(str(raw["floor"]), str(raw["map"]), str(raw["outside"]),
                              str(raw["inside"]), wait))
    if len(stops) < 2:
        raise ValueError("a lift serves at least two floors")
    return LiftConnection(str(data.get("car", name)), tuple(stops))


def _direct(name: str, data: dict[str, Any]) -> DirectConnection:
    a, b = data["from"], data["to"]
    return DirectConnection(name, str(a["map"]), str(a["point"]), str(b["map"]),
                            str(b["point"]))
