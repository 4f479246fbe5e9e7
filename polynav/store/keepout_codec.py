"""Keepouts as stored: a type name and JSON geometry, and back.

The shapes of :mod:`polynav.maps.keepout` keep their world coordinates [m] as JSON numbers,
which Python writes with ``repr`` precision, so a keepout reads back exactly as it was saved.
"""

from __future__ import annotations

import json
from typing import Any

from polynav.errors import InvalidRequest, StorageError
from polynav.maps.keepout import CircleZone, ForbiddenZone, GuidedZone, Keepout, VirtualWall

VIRTUAL_WALL = "virtual_wall"
FORBIDDEN_ZONE = "forbidden_zone"
CIRCLE_ZONE = "circle_zone"
GUIDED_ZONE = "guided_zone"
KEEPOUT_TYPES = (VIRTUAL_WALL, FORBIDDEN_ZONE, CIRCLE_ZONE, GUIDED_ZONE)


def encode(keepout: Keepout) -> tuple[str, str]:
    """The stored ``(type, geometry JSON)`` of ``keepout``.

    Raises:
        InvalidRequest: ``keepout`` is none of the keepout shapes.
    """
    if isinstance(keepout, VirtualWall):
        data: dict[str, Any] = {
            "points": [list(p) for p in keepout.points],
            "thickness": keepout.thickness,
        }
        return VIRTUAL_WALL, json.dumps(data)
    if isinstance(keepout, ForbiddenZone):
        return FORBIDDEN_ZONE, json.dumps({"polygon": [list(p) for p in keepout.polygon]})
    if isinstance(keepout, CircleZone):
        data = {"x": keepout.x, "y": keepout.y, "radius": keepout.radius}
        return CIRCLE_ZONE, json.dumps(data)
    if isinstance(keepout, GuidedZone):
        data = {"polygon": [list(p) for p in keepout.polygon],
                "route": [list(p) for p in keepout.route], "lane_width": keepout.lane_width,
                "start_waits": [list(p) for p in keepout.start_waits],
                "end_waits": [list(p) for p in keepout.end_waits]}
        return GUIDED_ZONE, json.dumps(data)
    raise InvalidRequest("keepouts", f"not a keepout shape: {type(keepout).__name__}")


def decode(kind: str, geometry: str) -> Keepout:
    """The keepout stored as ``(kind, geometry)``.

    Raises:
        StorageError: the stored row is not a keepout this version knows (a damaged database).
    """
    try:
        data = json.loads(geometry)
        if kind == VIRTUAL_WALL:
            return VirtualWall(
                tuple((float(x), float(y)) for x, y in data["points"]), float(data["thickness"])
            )
        if kind == FORBIDDEN_ZONE:
            return ForbiddenZone(tuple((float(x), float(y)) for x, y in data["polygon"]))
        if kind == CIRCLE_ZONE:
            return CircleZone(float(data["x"]), float(data["y"]), float(data["radius"]))
        if kind == GUIDED_ZONE:
            def pts(key: str) -> tuple[tuple[float, float], ...]:
                return tuple((float(x), float(y)) for x, y in data[key])

            return GuidedZone(pts("polygon"), pts("route"), float(data["lane_width"]),
                              pts("start_waits"), pts("end_waits"))
    except (ValueError, TypeError, KeyError) as exc:
        raise StorageError(f"damaged {kind} keepout in the site database: {exc}") from exc
    raise StorageError(f"unknown keepout type {kind!r} in the site database")
