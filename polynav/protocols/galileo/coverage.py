"""``POST /navigation/coverage_path`` (galileo-http-b E65): a boustrophedon path over a polygon.

The geometry is :mod:`polynav.planning.coverage`; this module converts the vendor's terms:
``swath_angle`` in degrees (``-3`` automatic, ``-2`` parallel to the shortest edge, ``-1`` to the
longest, ``0``–``180`` from the map x axis counter-clockwise, A-17), ``op_width`` the lane spacing,
``headland_width`` the strip kept along the edges, ``border``/``holes`` as ``[x, y, z]`` lists
(holes are honoured although the document says "not used yet"). Points are given every
``op_width`` along each lane, ``z`` = 0. ``turn_radius`` is checked (>= 0) but not used:
the path joins lane ends directly, and the robot's controller turns as it can. Nothing is stored
or run.
"""

from __future__ import annotations

import math
from typing import Any

from polynav.errors import InvalidRequest
from polynav.planning import coverage
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.endpoint import Reply, RouteList
from polynav.protocols.galileo.params import Params

ROUTES = RouteList()

_MODES = {-3: coverage.AUTO, -2: coverage.SHORTEST_EDGE, -1: coverage.LONGEST_EDGE}


def _points(field: str, value: Any) -> list[list[float]]:
    if not isinstance(value, list) or not all(
        isinstance(p, list) and 2 <= len(p) <= 3
        and all(isinstance(c, (int, float)) and not isinstance(c, bool) for c in p)
        for p in value
    ):
        raise InvalidRequest(field, "must be a list of [x, y, z] points")
    return value


@ROUTES.post("/navigation/coverage_path")
def coverage_path(ctx: Context, params: Params) -> Reply:
    """E65."""
    angle_deg = params.number("swath_angle")
    if angle_deg in _MODES:
        angle = _MODES[int(angle_deg)]
    elif 0.0 <= angle_deg <= 180.0:
        angle = math.radians(angle_deg)
    else:
        raise InvalidRequest("swath_angle", f"must be -3, -2, -1 or in [0, 180], got {angle_deg}")
    spacing = params.number("op_width")
    turn_radius = params.number("turn_radius")
    if turn_radius < 0:
        raise InvalidRequest("turn_radius", f"must be >= 0, got {turn_radius}")
    headland = params.number("headland_width")
    border = coverage.ring("border", _points("border", params.structure("border")))
    holes_raw = params.structure("holes", [])
    if not isinstance(holes_raw, list):
        raise InvalidRequest("holes", "must be a list of polygons")
    holes = tuple(coverage.ring("holes", _points("holes", h)) for h in holes_raw)
    request = coverage.CoverageRequest(border, holes, spacing, headland, angle, step=spacing)
    path = coverage.coverage_path(request)
    return {"status": "ok", "path": [[x, y, 0] for x, y in path]}
