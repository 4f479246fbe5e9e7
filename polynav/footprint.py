"""The robot's footprint: the shape of its body in its own frame, and whether it hits anything.

A footprint is a circle (a radius about the base origin) or a simple polygon (vertices in the
base frame, x forward, y left, [m]) that contains the origin. It is the one description of the body
that the simulator, the costmap and the controller share, so that they cannot disagree:

- the costmap inflates obstacles by :attr:`Footprint.inscribed_radius` (a cell closer than this to
  an obstacle is in collision for every heading) and uses :attr:`Footprint.circumscribed_radius`
  as the distance beyond which no heading collides (Nav2 ``calculateMinAndMaxDistances``);
- the controller asks :func:`first_collision` whether the footprint swept along the poses it is
  about to drive touches a LETHAL cell, and :func:`clearance` how far the body is from one.

The collision test is exact for the grid: a LETHAL cell is the full square it covers, and it hits
the footprint when that square and the shape overlap. Only LETHAL cells are obstacles here: the
INSCRIBED band is the costmap's conservative stand-in for a round robot, which is just what an
exact footprint check replaces. UNKNOWN cells and cells off the grid are free unless the caller
says otherwise (the planner decides whether unknown space may be crossed).

The kernels are numba-compiled and look at cell geometry only for the LETHAL cells inside the
footprint's bounding box, so a check costs little more than reading that box.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numba
import numpy as np
import numpy.typing as npt

from polynav.errors import ConfigError
from polynav.geometry import Pose2D
from polynav.maps import costs
from polynav.maps.interface import CostGrid
from polynav.maps.map import MapInfo

log = logging.getLogger(__name__)

_EPS = 1e-12
_LETHAL = costs.LETHAL
_UNKNOWN = costs.UNKNOWN


@dataclass(frozen=True, slots=True, eq=False)
class Footprint:
    """The shape of the robot in its base frame: a circle or a simple polygon [m].

    Build one with :meth:`circle`, :meth:`polygon` or :meth:`rectangle`; they validate the shape.

    Attributes:
        radius: the circle's radius [m]; 0 for a polygon.
        vertices: (M, 2) polygon vertices in the base frame, counter-clockwise; (0, 2) for a
            circle. Read-only.
        inscribed_radius: distance [m] from the origin to the nearest point of the outline.
        circumscribed_radius: distance [m] from the origin to the farthest point of the outline.
    """

    radius: float
    vertices: npt.NDArray[np.float64]
    inscribed_radius: float
    circumscribed_radius: float

    @classmethod
    def circle(cls, radius: float, *, key: str = "footprint") -> Footprint:
        """A round robot of ``radius`` [m] centred on the base origin.

        Raises:
            ConfigError: ``radius`` is not a finite number > 0 (named ``<key>.radius``).
        """
        if not (math.isfinite(radius) and radius > 0.0):
            raise ConfigError(f"{key}.radius", f"must be a finite number > 0, got {radius!r}")
        empty = np.zeros((0, 2), dtype=np.float64)
        empty.flags.writeable = False
        return cls(float(radius), empty, float(radius), float(radius))

    @classmethod
    def polygon(
        cls, vertices: Sequence[Sequence[float]] | npt.ArrayLike, *, key: str = "footprint"
    ) -> Footprint:
        """A polygonal robot from its outline in the base frame [m], either winding.

        Raises:
            ConfigError: fewer than 3 vertices, a non-finite coordinate, a repeated vertex, a
                zero-area or self-intersecting outline, or an outline that does not contain the
                base origin (named ``<key>.vertices``).
        """
        field = f"{key}.vertices"
        try:
            pts = np.array(vertices, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise ConfigError(field, f"must be a list of [x, y] pairs ({exc})") from exc
        if pts.ndim != 2 or pts.shape[1] != 2:
            raise ConfigError(field, f"must be a list of [x, y] pairs, got shape {pts.shape}")
        m = pts.shape[0]
        if m < 3:
            raise ConfigError(field, f"needs at least 3 vertices, got {m}")
        if not np.all(np.isfinite(pts)):
            raise ConfigError(field, "every coordinate must be finite")
        for i in range(m):
            j = (i + 1) % m
            if math.hypot(*(pts[j] - pts[i])) < 1e-9:
                raise ConfigError(field, f"vertices {i} and {j} coincide")
        crossing = _self_intersection(pts)
        if crossing is not None:
            a, b = crossing
            raise ConfigError(field, f"self-intersecting: edge {a} crosses edge {b}")
        area = _signed_area(pts)
        if abs(area) < 1e-12:
            raise ConfigError(field, "the outline encloses no area")
        if area < 0.0:
            pts = pts[::-1].copy()  # keep counter-clockwise so "inside" is "left of every edge"
        if not _contains(pts, 0.0, 0.0):
            raise ConfigError(field, "must contain the base origin (0, 0)")
        inscribed = min(
            _point_segment_distance(0.0, 0.0, *pts[i], *pts[(i + 1) % m]) for i in range(m)
        )
        circumscribed = float(np.max(np.hypot(pts[:, 0], pts[:, 1])))
        pts.flags.writeable = False
        return cls(0.0, pts, float(inscribed), circumscribed)

    @classmethod
    def rectangle(
        cls, length: float, width: float, *, offset_x: float = 0.0, key: str = "footprint"
    ) -> Footprint:
        """A rectangle ``length`` [m] along x by ``width`` [m] along y.

        Args:
            length: extent along the robot's heading [m].
            width: extent across it [m].
            offset_x: how far [m] the rectangle's centre lies ahead of the base origin (a
                differential drive's axle is often behind the centre).
        """
        if not (math.isfinite(length) and length > 0.0):
            raise ConfigError(f"{key}.length", f"must be a finite number > 0, got {length!r}")
        if not (math.isfinite(width) and width > 0.0):
            raise ConfigError(f"{key}.width", f"must be a finite number > 0, got {width!r}")
        hx, hy = 0.5 * length, 0.5 * width
        return cls.polygon(
            [
                (offset_x + hx, hy),
                (offset_x - hx, hy),
                (offset_x - hx, -hy),
                (offset_x + hx, -hy),
            ],
            key=key,
        )

    @property
    def is_circle(self) -> bool:
        return bool(self.vertices.shape[0] == 0)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Footprint):
            return NotImplemented
        return self.radius == other.radius and bool(np.array_equal(self.vertices, other.vertices))

    def __hash__(self) -> int:
        return hash((self.radius, self.vertices.tobytes()))

    def __repr__(self) -> str:
        if self.is_circle:
            return f"Footprint.circle({self.radius!r})"
        return f"Footprint.polygon({self.vertices.tolist()!r})"

    def outline(self, pose: Pose2D, *, segments: int = 32) -> npt.NDArray[np.float64]:
        """The outline (M, 2) [m] placed at ``pose``; a circle as a ``segments``-gon."""
        if self.is_circle:
            a = np.linspace(0.0, 2.0 * math.pi, segments, endpoint=False)
            local = np.column_stack((self.radius * np.cos(a), self.radius * np.sin(a)))
        else:
            local = self.vertices
        c, s = math.cos(pose.theta), math.sin(pose.theta)
        out = np.empty_like(local)
        out[:, 0] = pose.x + c * local[:, 0] - s * local[:, 1]
        out[:, 1] = pose.y + s * local[:, 0] + c * local[:, 1]
        return out

    def contains_point(self, pose: Pose2D, x: float, y: float) -> bool:
        """True if world point (x, y) [m] lies inside (or on) the footprint placed at ``pose``."""
        local = Pose2D(x, y).relative_to(pose)
        if self.is_circle:
            return math.hypot(local.x, local.y) <= self.radius
        return _contains(self.vertices, local.x, local.y)

    def covers(self, other: Footprint) -> bool:
        """True if this footprint contains ``other`` whole (both in the same base frame).

        The planning footprint must cover the body's: a planner that plans for a smaller robot
        sends the body into gaps it does not fit.
        """
        if self.is_circle:
            return other.circumscribed_radius <= self.radius + 1e-9
        if other.is_circle:
            # The disk is centred on the origin, inside this polygon: it fits if no edge is nearer.
            return self.inscribed_radius >= other.radius - 1e-9
        if not all(_contains(self.vertices, float(px), float(py)) for px, py in other.vertices):
            return False
        m, k = self.vertices.shape[0], other.vertices.shape[0]
        return not any(
            _segments_cross(
                self.vertices[i], self.vertices[(i + 1) % m],
                other.vertices[j], other.vertices[(j + 1) % k],
            )
            for i in range(m)
            for j in range(k)
        )

    def rotation_step(self, resolution: float) -> float:
        """Heading step [rad] at which the farthest point moves at most half a cell.

        Sampling a turn in place this finely checks the swept area, not just its two ends.
        """
        return min(0.5 * resolution / max(self.circumscribed_radius, _EPS), math.pi / 8.0)


def poses_array(poses: Sequence[Pose2D]) -> npt.NDArray[np.float64]:
    """Poses as an (N, 3) array of x, y, theta, the form the checks take."""
    out = np.empty((len(poses), 3), dtype=np.float64)
    for i, p in enumerate(poses):
        out[i] = (p.x, p.y, p.theta)
    return out


def rotation_poses(
    footprint: Footprint, pose: Pose2D, turn: float, resolution: float
) -> npt.NDArray[np.float64]:
    """Poses (N, 3) of a turn in place by ``turn`` [rad] from ``pose``, both ends included.

    Spaced by :meth:`Footprint.rotation_step`, so checking them checks the whole swept area.
    """
    n = max(int(math.ceil(abs(turn) / footprint.rotation_step(resolution))), 1)
    out = np.empty((n + 1, 3), dtype=np.float64)
    out[:, 0] = pose.x
    out[:, 1] = pose.y
    out[:, 2] = pose.theta + np.linspace(0.0, turn, n + 1)
    return out


def collides(
    footprint: Footprint, costmap: CostGrid, pose: Pose2D, *, unknown_is_lethal: bool = False
) -> bool:
    """True if the footprint at ``pose`` overlaps a LETHAL cell (see the module docstring)."""
    return first_collision(
        footprint, costmap, poses_array([pose]), unknown_is_lethal=unknown_is_lethal
    ) is not None


def first_collision(
    footprint: Footprint,
    costmap: CostGrid,
    poses: npt.NDArray[np.float64],
    *,
    unknown_is_lethal: bool = False,
) -> int | None:
    """Index of the first pose at which the footprint overlaps a LETHAL cell, or ``None``.

    Args:
        footprint: the body.
        costmap: costs ``[iy, ix]`` and their geometry.
        poses: (N, 3) rows of x [m], y [m], theta [rad] in the costmap's world frame, in the
            order the robot reaches them; sample them finely enough (half a cell of travel, see
            :func:`rotation_poses`) that nothing slips between two.
        unknown_is_lethal: treat UNKNOWN cells and cells off the grid as obstacles.
    """
    local = _to_grid_frame(costmap.info, poses)
    hit = _first_hit(
        np.ascontiguousarray(costmap.costs),
        costmap.info.resolution,
        footprint.vertices,
        footprint.radius,
        local,
        unknown_is_lethal,
    )
    return None if hit < 0 else int(hit)


def clearances(
    footprint: Footprint,
    costmap: CostGrid,
    poses: npt.NDArray[np.float64],
    *,
    horizon: float,
    unknown_is_lethal: bool = False,
) -> npt.NDArray[np.float64]:
    """Gap [m] between the footprint and the nearest LETHAL cell at each pose, up to ``horizon``.

    0 where the footprint overlaps one; ``horizon`` where nothing is nearer. The controller slows
    with this gap rather than stopping for it.
    """
    local = _to_grid_frame(costmap.info, poses)
    return _clearances(
        np.ascontiguousarray(costmap.costs),
        costmap.info.resolution,
        footprint.vertices,
        footprint.radius,
        local,
        float(horizon),
        unknown_is_lethal,
    )


def clearance(
    footprint: Footprint,
    costmap: CostGrid,
    pose: Pose2D,
    *,
    horizon: float,
    unknown_is_lethal: bool = False,
) -> float:
    """:func:`clearances` for one pose."""
    return float(
        clearances(
            footprint,
            costmap,
            poses_array([pose]),
            horizon=horizon,
            unknown_is_lethal=unknown_is_lethal,
        )[0]
    )


def _to_grid_frame(info: MapInfo, poses: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """Poses in the grid's own frame (origin at the corner of cell (0, 0), axes along the grid)."""
    p = np.asarray(poses, dtype=np.float64).reshape(-1, 3)
    o = info.origin
    c, s = math.cos(o.theta), math.sin(o.theta)
    dx, dy = p[:, 0] - o.x, p[:, 1] - o.y
    out = np.empty_like(p)
    out[:, 0] = c * dx + s * dy
    out[:, 1] = -s * dx + c * dy
    out[:, 2] = p[:, 2] - o.theta
    return out


# --- pure geometry (Python, used for validation) -------------------------------------------------


def _signed_area(pts: npt.NDArray[np.float64]) -> float:
    x, y = pts[:, 0], pts[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def _orient(ax: float, ay: float, bx: float, by: float, cx: float, cy: float) -> float:
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)


def _on_segment(ax: float, ay: float, bx: float, by: float, px: float, py: float) -> bool:
    return min(ax, bx) - 1e-12 <= px <= max(ax, bx) + 1e-12 and (
        min(ay, by) - 1e-12 <= py <= max(ay, by) + 1e-12
    )


def _segments_intersect(
    a: npt.NDArray[np.float64],
    b: npt.NDArray[np.float64],
    c: npt.NDArray[np.float64],
    d: npt.NDArray[np.float64],
) -> bool:
    d1 = _orient(*c, *d, *a)
    d2 = _orient(*c, *d, *b)
    d3 = _orient(*a, *b, *c)
    d4 = _orient(*a, *b, *d)
    if ((d1 > 0 > d2) or (d1 < 0 < d2)) and ((d3 > 0 > d4) or (d3 < 0 < d4)):
        return True
    tol = 1e-12
    return (
        (abs(d1) <= tol and _on_segment(*c, *d, *a))
        or (abs(d2) <= tol and _on_segment(*c, *d, *b))
        or (abs(d3) <= tol and _on_segment(*a, *b, *c))
        or (abs(d4) <= tol and _on_segment(*a, *b, *d))
    )


def _segments_cross(
    a: npt.NDArray[np.float64],
    b: npt.NDArray[np.float64],
    c: npt.NDArray[np.float64],
    d: npt.NDArray[np.float64],
) -> bool:
    """Do the segments cross properly (each strictly splits the other; touching is not)?"""
    d1, d2 = _orient(*c, *d, *a), _orient(*c, *d, *b)
    d3, d4 = _orient(*a, *b, *c), _orient(*a, *b, *d)
    return ((d1 > 1e-12 and d2 < -1e-12) or (d1 < -1e-12 and d2 > 1e-12)) and (
        (d3 > 1e-12 and d4 < -1e-12) or (d3 < -1e-12 and d4 > 1e-12)
    )


def _self_intersection(pts: npt.NDArray[np.float64]) -> tuple[int, int] | None:
    """The first pair of edges that touch other than at their shared vertex, or ``None``."""
    m = pts.shape[0]
    for i in range(m):
        a, b = pts[i], pts[(i + 1) % m]
        for j in range(i + 1, m):
            if j == i + 1 or (i == 0 and j == m - 1):
                # Neighbours share a vertex; they cross only if they fold back onto each other.
                c, d = pts[j], pts[(j + 1) % m]
                shared = b if j == i + 1 else a
                other_i = a if j == i + 1 else b
                other_j = d if j == i + 1 else c
                if abs(_orient(*other_i, *shared, *other_j)) <= 1e-12:
                    u = other_i - shared
                    v = other_j - shared
                    if float(np.dot(u, v)) > 0.0:
                        return (i, j)
                continue
            if _segments_intersect(a, b, pts[j], pts[(j + 1) % m]):
                return (i, j)
    return None


def _point_segment_distance(
    px: float, py: float, ax: float, ay: float, bx: float, by: float
) -> float:
    return float(_seg_dist(px, py, ax, ay, bx, by))


def _contains(pts: npt.NDArray[np.float64], x: float, y: float) -> bool:
    return bool(_inside_or_on(pts, x, y))


# --- kernels -------------------------------------------------------------------------------------


@numba.njit(cache=True, nogil=True)
def _seg_dist(px: float, py: float, ax: float, ay: float, bx: float, by: float) -> float:
    dx, dy = bx - ax, by - ay
    den = dx * dx + dy * dy
    t = 0.0
    if den > 0.0:
        t = ((px - ax) * dx + (py - ay) * dy) / den
        t = min(max(t, 0.0), 1.0)
    ex, ey = ax + t * dx - px, ay + t * dy - py
    return math.sqrt(ex * ex + ey * ey)


@numba.njit(cache=True, nogil=True)
def _inside_or_on(pts: npt.NDArray[np.float64], x: float, y: float) -> bool:
    """Even-odd point-in-polygon test; points on the outline count as inside."""
    m = pts.shape[0]
    inside = False
    for i in range(m):
        ax, ay = pts[i, 0], pts[i, 1]
        bx, by = pts[(i + 1) % m, 0], pts[(i + 1) % m, 1]
        if _seg_dist(x, y, ax, ay, bx, by) <= 1e-12:
            return True
        if (ay > y) != (by > y):
            xc = ax + (y - ay) * (bx - ax) / (by - ay)
            if x < xc:
                inside = not inside
    return inside


@numba.njit(cache=True, nogil=True)
def _segment_hits_box(
    ax: float, ay: float, bx: float, by: float, x0: float, y0: float, x1: float, y1: float
) -> bool:
    """Does segment a-b touch the axis-aligned box [x0, x1] x [y0, y1]? (Liang-Barsky clip)."""
    t0, t1 = 0.0, 1.0
    dx, dy = bx - ax, by - ay
    for k in range(4):
        if k == 0:
            p, q = -dx, ax - x0
        elif k == 1:
            p, q = dx, x1 - ax
        elif k == 2:
            p, q = -dy, ay - y0
        else:
            p, q = dy, y1 - ay
        if p == 0.0:
            if q < 0.0:
                return False
        else:
            r = q / p
            if p < 0.0:
                if r > t1:
                    return False
                if r > t0:
                    t0 = r
            else:
                if r < t0:
                    return False
                if r < t1:
                    t1 = r
    return True


@numba.njit(cache=True, nogil=True)
def _box_distance(px: float, py: float, x0: float, y0: float, x1: float, y1: float) -> float:
    dx = max(x0 - px, 0.0, px - x1)
    dy = max(y0 - py, 0.0, py - y1)
    return math.sqrt(dx * dx + dy * dy)


@numba.njit(cache=True, nogil=True)
def _cell_gap(
    world: npt.NDArray[np.float64],
    radius: float,
    cx: float,
    cy: float,
    x0: float,
    y0: float,
    x1: float,
    y1: float,
) -> float:
    """Gap [m] between the placed shape and the box [x0, x1] x [y0, y1]; 0 on overlap.

    ``world`` holds the placed polygon (M, 2), or is empty for a circle of ``radius`` at (cx, cy).
    """
    m = world.shape[0]
    if m == 0:
        return max(_box_distance(cx, cy, x0, y0, x1, y1) - radius, 0.0)
    mx, my = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
    if _inside_or_on(world, mx, my):
        return 0.0
    best = math.inf
    for i in range(m):
        ax, ay = world[i, 0], world[i, 1]
        bx, by = world[(i + 1) % m, 0], world[(i + 1) % m, 1]
        if _segment_hits_box(ax, ay, bx, by, x0, y0, x1, y1):
            return 0.0
        # Disjoint simple shapes are nearest at a vertex of one against an edge of the other.
        best = min(best, _box_distance(ax, ay, x0, y0, x1, y1))
        best = min(best, _seg_dist(x0, y0, ax, ay, bx, by))
        best = min(best, _seg_dist(x1, y0, ax, ay, bx, by))
        best = min(best, _seg_dist(x0, y1, ax, ay, bx, by))
        best = min(best, _seg_dist(x1, y1, ax, ay, bx, by))
    return best


@numba.njit(cache=True, nogil=True)
def _place(
    verts: npt.NDArray[np.float64], x: float, y: float, theta: float, out: npt.NDArray[np.float64]
) -> None:
    c, s = math.cos(theta), math.sin(theta)
    for i in range(verts.shape[0]):
        out[i, 0] = x + c * verts[i, 0] - s * verts[i, 1]
        out[i, 1] = y + s * verts[i, 0] + c * verts[i, 1]


@numba.njit(cache=True, nogil=True)
def _is_obstacle(grid: npt.NDArray[np.uint8], ix: int, iy: int, unknown_is_lethal: bool) -> bool:
    h, w = grid.shape
    if ix < 0 or iy < 0 or ix >= w or iy >= h:
        return unknown_is_lethal
    v = grid[iy, ix]
    if v == _LETHAL:
        return True
    return unknown_is_lethal and v == _UNKNOWN


@numba.njit(cache=True, nogil=True)
def _min_gap(
    grid: npt.NDArray[np.uint8],
    res: float,
    verts: npt.NDArray[np.float64],
    radius: float,
    x: float,
    y: float,
    theta: float,
    reach: float,
    horizon: float,
    unknown_is_lethal: bool,
    world: npt.NDArray[np.float64],
) -> float:
    """Smallest gap up to ``horizon`` from the placed shape to an obstacle cell within ``reach``."""
    _place(verts, x, y, theta, world)
    span = reach + horizon
    ix0 = int(math.floor((x - span) / res))
    ix1 = int(math.floor((x + span) / res))
    iy0 = int(math.floor((y - span) / res))
    iy1 = int(math.floor((y + span) / res))
    best = horizon
    for iy in range(iy0, iy1 + 1):
        y0 = iy * res
        for ix in range(ix0, ix1 + 1):
            if not _is_obstacle(grid, ix, iy, unknown_is_lethal):
                continue
            x0 = ix * res
            # The nearest the cell can be to any part of the shape is its distance to the
            # circumscribed circle; skip the exact test when even that is no better.
            if _box_distance(x, y, x0, y0, x0 + res, y0 + res) - reach >= best:
                continue
            gap = _cell_gap(world, radius, x, y, x0, y0, x0 + res, y0 + res)
            if gap < best:
                best = gap
                if best <= 0.0:
                    return 0.0
    return best


@numba.njit(cache=True, nogil=True)
def _overlaps(
    grid: npt.NDArray[np.uint8],
    res: float,
    verts: npt.NDArray[np.float64],
    radius: float,
    x: float,
    y: float,
    theta: float,
    reach: float,
    unknown_is_lethal: bool,
    world: npt.NDArray[np.float64],
) -> bool:
    """Does the shape placed at (x, y, theta) overlap an obstacle cell?"""
    _place(verts, x, y, theta, world)
    ix0 = int(math.floor((x - reach) / res))
    ix1 = int(math.floor((x + reach) / res))
    iy0 = int(math.floor((y - reach) / res))
    iy1 = int(math.floor((y + reach) / res))
    for iy in range(iy0, iy1 + 1):
        y0 = iy * res
        for ix in range(ix0, ix1 + 1):
            if not _is_obstacle(grid, ix, iy, unknown_is_lethal):
                continue
            x0 = ix * res
            if _box_distance(x, y, x0, y0, x0 + res, y0 + res) > reach:
                continue
            if _cell_gap(world, radius, x, y, x0, y0, x0 + res, y0 + res) <= 0.0:
                return True
    return False


@numba.njit(cache=True, nogil=True)
def _reach(verts: npt.NDArray[np.float64], radius: float) -> float:
    reach = radius
    for i in range(verts.shape[0]):
        reach = max(reach, math.sqrt(verts[i, 0] ** 2 + verts[i, 1] ** 2))
    return reach


@numba.njit(cache=True, nogil=True)
def _first_hit(
    grid: npt.NDArray[np.uint8],
    res: float,
    verts: npt.NDArray[np.float64],
    radius: float,
    poses: npt.NDArray[np.float64],
    unknown_is_lethal: bool,
) -> int:
    world = np.empty_like(verts)
    reach = _reach(verts, radius)
    for k in range(poses.shape[0]):
        if _overlaps(grid, res, verts, radius, poses[k, 0], poses[k, 1], poses[k, 2],
                     reach, unknown_is_lethal, world):
            return k
    return -1


@numba.njit(cache=True, nogil=True)
def _clearances(
    grid: npt.NDArray[np.uint8],
    res: float,
    verts: npt.NDArray[np.float64],
    radius: float,
    poses: npt.NDArray[np.float64],
    horizon: float,
    unknown_is_lethal: bool,
) -> npt.NDArray[np.float64]:
    world = np.empty_like(verts)
    reach = _reach(verts, radius)
    out = np.empty(poses.shape[0], dtype=np.float64)
    for k in range(poses.shape[0]):
        out[k] = _min_gap(grid, res, verts, radius, poses[k, 0], poses[k, 1], poses[k, 2],
                          reach, horizon, unknown_is_lethal, world)
    return out


def warm_up() -> None:
    """Compile the kernels on tiny inputs (the runtime calls this at start-up)."""
    grid = np.zeros((4, 4), dtype=np.uint8)
    grid[1, 1] = costs.LETHAL
    snapshot = _Snapshot(MapInfo(resolution=1.0, width=4, height=4), grid)
    poses = np.array([[2.5, 2.5, 0.0]])
    for fp in (Footprint.circle(0.4), Footprint.rectangle(0.8, 0.6)):
        first_collision(fp, snapshot, poses)
        clearances(fp, snapshot, poses, horizon=1.0)


@dataclass(frozen=True, slots=True, eq=False)
class _Snapshot:
    info: MapInfo
    costs: npt.NDArray[np.uint8]
