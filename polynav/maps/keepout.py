"""Keepouts: places the user forbids the robot to go, drawn on top of the map.

Four shapes, all in world coordinates [m] so they survive a map being re-made at another
resolution: a :class:`VirtualWall` (a polyline with a thickness, Galileo's "virtual wall"), a
:class:`ForbiddenZone` (a filled polygon, Galileo's "ignore area"), a :class:`CircleZone`, and
a :class:`GuidedZone` (a filled polygon but for a lane along its route: a "special region").
:func:`rasterize` turns a set of them into the cells the keepout layer makes lethal.

Rasterisation rules, chosen so that a keepout never leaks and never silently vanishes:

* a wall covers every cell its centre line passes through (a 4-connected chain, so even an
  8-connected planner that cuts corners cannot slip through a diagonal gap) plus every cell whose
  centre lies within ``thickness / 2`` of the line, so it is at least one cell wide;
* a zone covers the cells whose centre lies inside it (the usual scan-line fill rule, so a square
  drawn on cell borders covers exactly the cells inside); a zone too thin to hold any cell centre
  falls back to the cells its outline passes through;
* a circle covers the cells whose centre lies within the radius, and always the cell holding its
  centre;
* a guided zone covers what its polygon would, less what a wall along its route as thick as the
  lane would.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from polynav.errors import InvalidRequest
from polynav.maps.map import MapInfo

log = logging.getLogger(__name__)

Point2 = tuple[float, float]


def _points(field: str, raw: Sequence[Sequence[float]], minimum: int) -> tuple[Point2, ...]:
    pts: list[Point2] = []
    for p in raw:
        try:
            x, y = p
            pts.append((float(x), float(y)))
        except (TypeError, ValueError) as exc:
            raise InvalidRequest(field, f"expected (x, y) pairs, got {p!r}") from exc
    if len(pts) < minimum:
        raise InvalidRequest(field, f"needs at least {minimum} points, got {len(pts)}")
    if not all(math.isfinite(c) for p in pts for c in p):
        raise InvalidRequest(field, "coordinates must be finite")
    return tuple(pts)


@dataclass(frozen=True, slots=True)
class VirtualWall:
    """A wall the robot must not cross: a polyline of world points [m] and a thickness [m].

    A thickness of 0 still draws a line one cell wide.
    """

    points: tuple[Point2, ...]
    thickness: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "points", _points("keepout.points", self.points, 1))
        if not (math.isfinite(self.thickness) and self.thickness >= 0.0):
            raise InvalidRequest("keepout.thickness", f"must be >= 0, got {self.thickness}")


@dataclass(frozen=True, slots=True)
class ForbiddenZone:
    """An area the robot must not enter: a simple polygon of world points [m], filled."""

    polygon: tuple[Point2, ...]

    def __post_init__(self) -> None:
        object.__setattr__(self, "polygon", _points("keepout.polygon", self.polygon, 3))


@dataclass(frozen=True, slots=True)
class CircleZone:
    """A round area the robot must not enter: centre (x, y) [m] and radius [m]."""

    x: float
    y: float
    radius: float

    def __post_init__(self) -> None:
        if not (math.isfinite(self.x) and math.isfinite(self.y)):
            raise InvalidRequest("keepout.centre", "coordinates must be finite")
        if not (math.isfinite(self.radius) and self.radius > 0.0):
            raise InvalidRequest("keepout.radius", f"must be > 0, got {self.radius}")


@dataclass(frozen=True, slots=True)
class GuidedZone:
    """An area the robot crosses only along its route: a simple polygon [m], filled, but for
    the lane ``lane_width`` wide along the ``route`` polyline (the androidmsg and Yunji "special
    region"). ``start_waits`` and ``end_waits`` are where a robot waits before entering from
    either end while another robot is in the zone; they are kept with it for the fleet."""

    polygon: tuple[Point2, ...]
    route: tuple[Point2, ...]
    lane_width: float = 1.2
    start_waits: tuple[Point2, ...] = ()
    end_waits: tuple[Point2, ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "polygon", _points("keepout.polygon", self.polygon, 3))
        object.__setattr__(self, "route", _points("keepout.route", self.route, 2))
        object.__setattr__(self, "start_waits", _points("keepout.start_waits",
                                                        self.start_waits, 0))
        object.__setattr__(self, "end_waits", _points("keepout.end_waits", self.end_waits, 0))
        if not (math.isfinite(self.lane_width) and self.lane_width > 0.0):
            raise InvalidRequest("keepout.lane_width", f"must be > 0, got {self.lane_width}")


Keepout = VirtualWall | ForbiddenZone | CircleZone | GuidedZone


def rasterize(keepouts: Sequence[Keepout], info: MapInfo) -> npt.NDArray[np.bool_]:
    """Cells ``[iy, ix]`` covered by any of ``keepouts`` on the grid ``info`` (rules above)."""
    mask = np.zeros((info.height, info.width), dtype=np.bool_)
    for keepout in keepouts:
        if isinstance(keepout, VirtualWall):
            _draw_wall(mask, info, keepout)
        elif isinstance(keepout, ForbiddenZone):
            _draw_zone(mask, info, keepout)
        elif isinstance(keepout, GuidedZone):
            _draw_guided(mask, info, keepout)
        else:
            _draw_circle(mask, info, keepout)
    return mask


def _local(info: MapInfo, pts: Sequence[Point2]) -> npt.NDArray[np.float64]:
    """Points in the grid frame, in cells: (0, 0) is the lower-left corner of cell (0, 0)."""
    to_grid = info.origin.inverse()
    return np.array([to_grid.transform_point(x, y) for x, y in pts]) / info.resolution


def _window(
    info: MapInfo, lo: npt.NDArray[np.float64], hi: npt.NDArray[np.float64]
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], tuple[slice, slice]] | None:
    """Cell-centre coordinates of the cells overlapping the grid box ``[lo, hi]``, clipped."""
    ix0 = max(int(math.floor(lo[0])), 0)
    iy0 = max(int(math.floor(lo[1])), 0)
    ix1 = min(int(math.floor(hi[0])) + 1, info.width)
    iy1 = min(int(math.floor(hi[1])) + 1, info.height)
    if ix0 >= ix1 or iy0 >= iy1:
        return None
    cx, cy = np.meshgrid(np.arange(ix0, ix1) + 0.5, np.arange(iy0, iy1) + 0.5)
    return cx, cy, (slice(iy0, iy1), slice(ix0, ix1))


def _walk(x0: float, y0: float, x1: float, y1: float) -> Iterator[tuple[int, int]]:
    """Cells a segment passes through, in grid units (Amanatides & Woo, Eurographics 1987)."""
    ix, iy = math.floor(x0), math.floor(y0)
    end = (math.floor(x1), math.floor(y1))
    dx, dy = x1 - x0, y1 - y0
    step_x = 1 if dx > 0 else -1
    step_y = 1 if dy > 0 else -1
    t_delta_x = abs(1.0 / dx) if dx != 0 else math.inf
    t_delta_y = abs(1.0 / dy) if dy != 0 else math.inf
    t_max_x = ((ix + 1 - x0) if dx > 0 else (x0 - ix)) * t_delta_x if dx != 0 else math.inf
    t_max_y = ((iy + 1 - y0) if dy > 0 else (y0 - iy)) * t_delta_y if dy != 0 else math.inf
    yield ix, iy
    while (ix, iy) != end and min(t_max_x, t_max_y) <= 1.0:
        if t_max_x < t_max_y:
            ix += step_x
            t_max_x += t_delta_x
        else:
            iy += step_y
            t_max_y += t_delta_y
        yield ix, iy


def _mark_walk(
    mask: npt.NDArray[np.bool_], a: npt.NDArray[np.float64], b: npt.NDArray[np.float64]
) -> None:
    height, width = mask.shape
    for ix, iy in _walk(float(a[0]), float(a[1]), float(b[0]), float(b[1])):
        if 0 <= ix < width and 0 <= iy < height:
            mask[iy, ix] = True


def _draw_wall(mask: npt.NDArray[np.bool_], info: MapInfo, wall: VirtualWall) -> None:
    pts = _local(info, wall.points)
    half = 0.5 * wall.thickness / info.resolution
    if len(pts) == 1:
        pts = np.vstack([pts, pts])
    for a, b in zip(pts[:-1], pts[1:], strict=True):
        _mark_walk(mask, a, b)
        if half <= 0.0:
            continue
        found = _window(info, np.minimum(a, b) - half, np.maximum(a, b) + half)
        if found is None:
            continue
        cx, cy, region = found
        ab = b - a
        length2 = float(ab @ ab)
        if length2 > 0.0:
            t = ((cx - a[0]) * ab[0] + (cy - a[1]) * ab[1]) / length2
            t = np.clip(t, 0.0, 1.0)
        else:
            t = np.zeros_like(cx)
        dist2 = (cx - a[0] - t * ab[0]) ** 2 + (cy - a[1] - t * ab[1]) ** 2
        # A tiny tolerance so a centre exactly at thickness / 2 counts, despite rounding.
        mask[region] |= dist2 <= half * half + 1e-9


def _draw_zone(mask: npt.NDArray[np.bool_], info: MapInfo, zone: ForbiddenZone) -> None:
    pts = _local(info, zone.polygon)
    found = _window(info, pts.min(axis=0), pts.max(axis=0))
    inside_any = False
    if found is not None:
        cx, cy, region = found
        inside = np.zeros(cx.shape, dtype=np.bool_)
        # Even-odd crossing test, vectorised over the cell centres, one edge at a time.
        for a, b in zip(pts, np.roll(pts, -1, axis=0), strict=True):
            if a[1] == b[1]:
                continue
            straddles = (a[1] > cy) != (b[1] > cy)
            x_cross = a[0] + (cy - a[1]) * (b[0] - a[0]) / (b[1] - a[1])
            inside ^= straddles & (cx < x_cross)
        mask[region] |= inside
        inside_any = bool(inside.any())
    if not inside_any:
        for a, b in zip(pts, np.roll(pts, -1, axis=0), strict=True):
            _mark_walk(mask, a, b)


def _draw_guided(mask: npt.NDArray[np.bool_], info: MapInfo, zone: GuidedZone) -> None:
    area = np.zeros_like(mask)
    _draw_zone(area, info, ForbiddenZone(zone.polygon))
    lane = np.zeros_like(mask)
    _draw_wall(lane, info, VirtualWall(zone.route, zone.lane_width))
    mask |= area & ~lane


def _draw_circle(mask: npt.NDArray[np.bool_], info: MapInfo, circle: CircleZone) -> None:
    centre = _local(info, [(circle.x, circle.y)])[0]
    radius = circle.radius / info.resolution
    found = _window(info, centre - radius, centre + radius)
    if found is not None:
        cx, cy, region = found
        mask[region] |= (cx - centre[0]) ** 2 + (cy - centre[1]) ** 2 <= radius * radius + 1e-9
    _mark_walk(mask, centre, centre)
