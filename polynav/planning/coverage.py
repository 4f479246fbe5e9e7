"""Boustrophedon coverage of a polygon: parallel lanes ``spacing`` apart, driven back and forth.

A field (an outer ring, with optional holes) is worked in straight lanes. Every lane is a line
at the swath angle; the worked part of a line is where it lies inside the field (even-odd rule
over all rings, so holes are left out) and at least ``headland`` from every ring edge (the
strip kept for turning). Lane ``k`` lies at offset ``(k + 1/2) * spacing`` across the field from
its first extreme point, so neighbouring lanes' swaths touch and the outer ones reach the
field's edge. Lanes are driven alternately forwards and backwards (boustrophedon); a lane cut
in several pieces by a hole or a concave edge is driven piece by piece in the same direction.

The swath angle is measured from the map x axis, counter-clockwise. Four ways to choose it
(galileo-http-b E65): a given angle; parallel to the longest or the shortest edge of the outer
ring; or automatic: the direction across which the field is narrowest (fewest lanes, so fewest
turns), searched over every edge direction and every whole degree.

Pure functions over tuples; no I/O. Reference: H. Choset, "Coverage of known spaces: the
boustrophedon cellular decomposition", Autonomous Robots 9 (2000).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence
from dataclasses import dataclass

from polynav.errors import InvalidRequest

log = logging.getLogger(__name__)

Point2 = tuple[float, float]
Ring = tuple[Point2, ...]

AUTO = -3.0
SHORTEST_EDGE = -2.0
LONGEST_EDGE = -1.0
MAX_LANES = 20_000
_EPS = 1e-9


@dataclass(frozen=True, slots=True)
class CoverageRequest:
    """What to cover and how.

    Attributes:
        border: the outer ring [m] (closed or not).
        holes: rings left out.
        spacing: distance between neighbouring lanes [m] (the working width).
        headland: strip along every edge kept free of lanes [m].
        swath_angle: lane direction [rad] from the x axis, or ``AUTO``, ``SHORTEST_EDGE``,
            ``LONGEST_EDGE``.
        step: distance between output points along a lane [m]; 0: lane ends only.
    """

    border: Ring
    holes: tuple[Ring, ...] = ()
    spacing: float = 0.5
    headland: float = 0.0
    swath_angle: float = AUTO
    step: float = 0.0


def ring(field: str, points: Sequence[Sequence[float]]) -> Ring:
    """A checked ring: closing point dropped, repeated points merged.

    Raises:
        InvalidRequest: fewer than 3 distinct points, no area, or non-finite values.
    """
    out: list[Point2] = []
    for p in points:
        if len(p) < 2:
            raise InvalidRequest(field, f"a point needs x and y, got {list(p)}")
        x, y = float(p[0]), float(p[1])
        if not (math.isfinite(x) and math.isfinite(y)):
            raise InvalidRequest(field, "coordinates must be finite")
        if not out or math.dist(out[-1], (x, y)) > _EPS:
            out.append((x, y))
    if len(out) > 1 and math.dist(out[0], out[-1]) <= _EPS:
        out.pop()
    if len(out) < 3 or abs(_area(out)) < 1e-9:
        raise InvalidRequest(field, "a polygon needs at least 3 distinct points and an area")
    return tuple(out)


def _area(pts: Sequence[Point2]) -> float:
    return 0.5 * sum(x0 * y1 - x1 * y0
                     for (x0, y0), (x1, y1) in zip(pts, [*pts[1:], pts[0]], strict=True))


def _edges(r: Ring) -> list[tuple[Point2, Point2]]:
    return list(zip(r, [*r[1:], r[0]], strict=True))


def lane_angle(request: CoverageRequest) -> float:
    """The lane direction [rad] in [0, π) for the request's swath mode."""
    mode = request.swath_angle
    edges = [(a, b) for a, b in _edges(request.border) if math.dist(a, b) > _EPS]
    if mode in (LONGEST_EDGE, SHORTEST_EDGE):
        pick = max if mode == LONGEST_EDGE else min
        a, b = pick(edges, key=lambda e: math.dist(*e))
        return math.atan2(b[1] - a[1], b[0] - a[0]) % math.pi
    if mode == AUTO:
        candidates = {math.atan2(b[1] - a[1], b[0] - a[0]) % math.pi for a, b in edges}
        candidates.update(math.radians(d) for d in range(180))
        return min(sorted(candidates), key=lambda t: _width_across(request.border, t))
    return mode % math.pi


def _width_across(r: Ring, angle: float) -> float:
    nx, ny = -math.sin(angle), math.cos(angle)
    offsets = [x * nx + y * ny for x, y in r]
    return max(offsets) - min(offsets)


def _line_crossings(rings: Sequence[Ring], origin: Point2, d: Point2) -> list[float]:
    """Parameters ``t`` where the line ``origin + t d`` crosses ring edges (half-open rule, so
    a vertex on the line counts once)."""
    ox, oy = origin
    dx, dy = d
    nx, ny = -dy, dx
    out: list[float] = []
    for r in rings:
        for (ax, ay), (bx, by) in _edges(r):
            sa = (ax - ox) * nx + (ay - oy) * ny
            sb = (bx - ox) * nx + (by - oy) * ny
            if (sa > 0) == (sb > 0):
                continue
            f = sa / (sa - sb)
            px, py = ax + f * (bx - ax), ay + f * (by - ay)
            out.append((px - ox) * dx + (py - oy) * dy)
    return sorted(out)


def _near_edge(a: Point2, b: Point2, origin: Point2, d: Point2, h: float
               ) -> tuple[float, float] | None:
    """The interval of ``t`` where ``origin + t d`` is closer than ``h`` to segment ``a b``
    (the line meets a stadium, a convex set, in one interval)."""
    ts: list[float] = []
    ox, oy = origin
    dx, dy = d
    for cx, cy in (a, b):  # the discs at the ends
        px, py = ox - cx, oy - cy
        bq = px * dx + py * dy
        c = px * px + py * py - h * h
        disc = bq * bq - c
        if disc > 0:
            root = math.sqrt(disc)
            ts += [-bq - root, -bq + root]
    ex, ey = b[0] - a[0], b[1] - a[1]
    length = math.hypot(ex, ey)
    if length > _EPS:  # the rectangle along the segment: clip the line by its four sides
        ux, uy = ex / length, ey / length
        lo, hi = -math.inf, math.inf
        for (qx, qy), low, high in (((ux, uy), 0.0, length), ((-uy, ux), -h, h)):
            s0 = (ox - a[0]) * qx + (oy - a[1]) * qy
            rate = dx * qx + dy * qy
            if abs(rate) < _EPS:
                if not low < s0 < high:  # a lane exactly headland away is kept
                    lo, hi = math.inf, -math.inf
                continue
            t1, t2 = (low - s0) / rate, (high - s0) / rate
            lo, hi = max(lo, min(t1, t2)), min(hi, max(t1, t2))
        if lo < hi:
            ts += [lo, hi]
    if not ts:
        return None
    return min(ts), max(ts)


def _subtract(intervals: list[tuple[float, float]], cut: tuple[float, float]
              ) -> list[tuple[float, float]]:
    out = []
    for lo, hi in intervals:
        if cut[1] <= lo or cut[0] >= hi:
            out.append((lo, hi))
            continue
        if cut[0] > lo:
            out.append((lo, cut[0]))
        if cut[1] < hi:
            out.append((cut[1], hi))
    return out


def lanes(request: CoverageRequest) -> list[list[tuple[Point2, Point2]]]:
    """The worked pieces of every lane, lane by lane across the field, each piece as its two
    ends in the lane's forward direction."""
    if not (math.isfinite(request.spacing) and request.spacing > 0):
        raise InvalidRequest("op_width", f"must be > 0, got {request.spacing}")
    if not (math.isfinite(request.headland) and request.headland >= 0):
        raise InvalidRequest("headland_width", f"must be >= 0, got {request.headland}")
    angle = lane_angle(request)
    d = (math.cos(angle), math.sin(angle))
    n = (-d[1], d[0])
    rings = (request.border, *request.holes)
    offsets = [x * n[0] + y * n[1] for x, y in request.border]
    low, high = min(offsets), max(offsets)
    count = max(1, math.ceil((high - low) / request.spacing - 1e-9))
    if count > MAX_LANES:
        raise InvalidRequest("op_width", f"{count} lanes: more than {MAX_LANES}")
    edges = [e for r in rings for e in _edges(r)]
    out: list[list[tuple[Point2, Point2]]] = []
    for k in range(count):
        offset = min(low + (k + 0.5) * request.spacing, high - 1e-6)
        origin = (n[0] * offset, n[1] * offset)
        ts = _line_crossings(rings, origin, d)
        inside = [(ts[i], ts[i + 1]) for i in range(0, len(ts) - 1, 2)]
        if request.headland > 0:
            for a, b in edges:
                cut = _near_edge(a, b, origin, d, request.headland)
                if cut is not None:
                    inside = _subtract(inside, cut)
        pieces = [((origin[0] + lo * d[0], origin[1] + lo * d[1]),
                   (origin[0] + hi * d[0], origin[1] + hi * d[1]))
                  for lo, hi in inside if hi - lo > 1e-6]
        if pieces:
            out.append(pieces)
    return out


def coverage_path(request: CoverageRequest) -> list[Point2]:
    """The boustrophedon path: lanes in order, every other one driven backwards.

    Raises:
        InvalidRequest: a bad spacing or headland, or too many lanes.
    """
    path: list[Point2] = []
    for index, pieces in enumerate(lanes(request)):
        ordered = pieces if index % 2 == 0 else [(b, a) for a, b in reversed(pieces)]
        for a, b in ordered:
            path.extend(_sample(a, b, request.step))
    return path


def _sample(a: Point2, b: Point2, step: float) -> list[Point2]:
    length = math.dist(a, b)
    if step <= 0 or length <= step:
        return [a, b]
    count = math.ceil(length / step - 1e-9)
    return [(a[0] + (b[0] - a[0]) * i / count, a[1] + (b[1] - a[1]) * i / count)
            for i in range(count + 1)]
