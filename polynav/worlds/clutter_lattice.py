"""The ``lattice`` kind of clutter course: walls of packed posts, hooks, pockets and tight gaps.

Issue 31's courses that look like the world. The ``posts`` kind keeps every gap a body width
plus a margin wide and lets the straight line through; real clutter does not. Here posts stand
on a lattice (``pitch`` [m], at most two post radii, so neighbours touch and a run of posts is a
short wall) and are grouped into structures, drawn from a seed and a *density* in 0..1:

1. A walled box, ``span + 3`` x ``width`` inside, start 1.5 m from one end wall, the goal
   ``span`` [m] further along the centre line, as in the ``posts`` kind.
2. *Barriers* across the box (1 at density 0, 3 at density 1, spread evenly), each from wall to
   wall, open only where the way crosses it and at a *gate*: a gap whose width lies between the
   body's width (2 x inscribed radius) and its diagonal (2 x circumscribed radius), on the
   straight line from start to goal. Some barriers (10 % at density 0, 30 % at 1) are
   *chicanes*: a second wall behind the first, a corridor as narrow between them, and the second
   gap just beside the first, away from the way. The planner, inflating by the inscribed radius,
   sees these open; a rectangular body fits a gate only lined up with it, and cannot turn in a
   chicane at all.
3. The *way*: a polyline from start to goal that passes each barrier level, 1.6 m or more off
   the centre line, on alternating sides, so it winds across the box and a gate on the straight
   line looks much shorter. Nothing is placed closer to it than ``max(way_clearance,
   circumscribed radius + lane_margin)`` (the way's clearance; barrier posts there are left
   out), so the body can drive it at any heading and turn anywhere on it.
4. Random structures between the barriers: straight walls, hooks (L and J shapes), pockets
   (U shapes open towards the start, so a robot heading for the goal drives into them), small
   boxes narrower than the body, and slots (two parallel walls as far apart as a gate is
   wide). Some pockets sit on the straight line. Their count grows with the density.
5. The guarantee is *checked* (:func:`check`): the exact distance from the way's centre line to
   every occupied cell (a cell is its full square) is at least the way's clearance, and the
   body's planner (:func:`polynav.planning.registry.for_footprint`: the grid planner for a
   disk, the footprint planner for a polygon) finds a route on the static map, planned with no
   cost penalty. Its length is ``optimal_length``: the shortest route the body can drive (for a
   polygon up to the lattice's 16 headings; turning in place takes no length).

What the generator placed is kept on the course (``structures``, and ``gaps`` with their
widths measured on the drawn grid) so tests and readers of a failed run can see it.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from polynav.errors import PolynavError
from polynav.footprint import Footprint
from polynav.geometry import Pose2D
from polynav.maps.costmap import Costmap
from polynav.maps.map import Map
from polynav.planning import registry
from polynav.planning.grid_planner import GridPlannerConfig
from polynav.planning.path import Path
from polynav.worlds.clutter_course import (
    RESOLUTION,
    WALL,
    ClutterCourse,
    ClutterSpec,
    Gap,
    Structure,
    box_cells,
    clearance_along,
    one_floor_world,
    static_config,
)

log = logging.getLogger(__name__)

Cell = tuple[int, int]  # (ix, iy)

WAY_OFFSET = 1.6  # [m] least distance of the way from the centre line where it passes a barrier
WAY_BEFORE = 0.7  # [m] the way runs level from this far before a barrier ...
WAY_AFTER = 1.4  # [m] ... to this far after it (past a chicane's second wall)
BARRIERS = 3  # at density 1
CHICANE_ODDS = (0.1, 0.3)  # chance that a barrier is a chicane, at density 0 and 1
BAND = 0.7  # [m] around a barrier kept free of random structures
GAP_MARGIN = 0.03  # [m] a tight gap's width stays this far inside (body width, diagonal)
CHICANE_SHIFT = (0.05, 0.35)  # [m] sideways distance between a chicane's two gaps
NEAR_LINE = 1.2  # [m] half-width of the band along the straight line half the structures go in
OPENING_ROOM = 0.3  # [m] around a deliberate opening kept free of later structures
STRUCTURE_KINDS = ("wall", "hook", "pocket", "box", "slot")
KIND_WEIGHTS = (0.25, 0.25, 0.2, 0.15, 0.15)
_AXES: tuple[Cell, ...] = ((1, 0), (0, 1), (-1, 0), (0, -1))


@dataclass(frozen=True, slots=True)
class _Frame:
    """The drawn box and the figures every placement step needs (cells are the grid's)."""

    footprint: Footprint
    spec: ClutterSpec
    start: Pose2D
    goal: Pose2D
    way: npt.NDArray[np.float64]
    barriers: tuple[float, ...]  # x [m] of each barrier's first wall
    clearance: float  # [m] the way's guaranteed clearance
    stamp: tuple[Cell, ...]  # cells one post covers, about its own cell
    arm: int  # cells a post reaches from its centre cell along an axis
    reach: float  # [m] farthest a post's cells extend from its centre
    step: int  # lattice pitch [cells]
    nx: int
    ny: int

    def centre(self, cell: Cell) -> tuple[float, float]:
        return ((cell[0] + 0.5) * RESOLUTION, (cell[1] + 0.5) * RESOLUTION)

    def cell(self, x: float, y: float) -> Cell:
        return (int(x // RESOLUTION), int(y // RESOLUTION))

    def tight_width(self, rng: np.random.Generator) -> int:
        """A gap width [cells] between the body's width and its diagonal (for a round body,
        whose two are equal, a little over its width)."""
        width, diagonal = (2.0 * self.footprint.inscribed_radius,
                           2.0 * self.footprint.circumscribed_radius)
        lo = width + GAP_MARGIN
        hi = max(diagonal - GAP_MARGIN, lo + 0.1)
        n = int(math.ceil(float(rng.uniform(lo, hi)) / RESOLUTION))
        # Whole cells round up; never up to the diagonal itself.
        while diagonal > lo and n * RESOLUTION >= diagonal and (n - 1) * RESOLUTION > width:
            n -= 1
        return n

    def clear_of_way(self, cells: list[Cell]) -> npt.NDArray[np.bool_]:
        """Per post cell: do its cells stay clear of the way by the way's clearance?"""
        if not cells:
            return np.zeros(0, dtype=bool)
        c = np.asarray(cells, dtype=np.float64)
        pts = (c + 0.5) * RESOLUTION
        return _distances_to_polyline(pts, self.way) >= self.clearance + self.reach + 0.01

    def inside(self, cells: list[Cell]) -> bool:
        """Every post stands inside the box (walls excluded)."""
        w = round(WALL / RESOLUTION)
        return all(w <= ix < self.nx - w and w <= iy < self.ny - w for ix, iy in cells)


def draw_once(
    footprint: Footprint, spec: ClutterSpec, rng: np.random.Generator, seed: int
) -> ClutterCourse:
    """One unchecked draw of a ``lattice`` course (see the module docstring)."""
    frame = _frame(footprint, spec, rng)
    posts: set[Cell] = set()
    structures: list[Structure] = []
    openings: list[tuple[Cell, Cell]] = []  # (centre cell, axis) of each deliberate gap
    bands = _barriers(frame, rng, posts, structures, openings)
    _line_pockets(frame, rng, posts, structures, bands)
    _random_structures(frame, rng, posts, structures, openings, bands)
    grid = _rasterize(frame, posts)
    gaps = tuple(g for g in (_measure(frame, grid, c, a) for c, a in openings) if g is not None)
    static = Costmap.from_map(grid, static_config(footprint))
    try:
        # No cost penalty: the shortest route the body can drive on the static map.
        planner = registry.for_footprint(footprint, GridPlannerConfig(cost_weight=0.0))
        path = planner.plan(static, frame.start, frame.goal)
    except PolynavError as exc:
        path = Path(np.zeros((0, 2)))
        log.warning("clutter lattice course %d: no path on the static map: %s", seed, exc)
    centres = np.asarray([frame.centre(c) for c in sorted(posts)], dtype=np.float64)
    widths = [g.width for g in gaps]
    return ClutterCourse(
        one_floor_world(grid, frame.start, seed), frame.start, frame.goal,
        centres.reshape(-1, 2), min(widths, default=0.0), path, kind="lattice",
        structures=tuple(structures), gaps=gaps, way=frame.way, way_clearance=frame.clearance,
    )


def check(course: ClutterCourse, footprint: Footprint) -> str | None:
    """``None`` if the course's way keeps its clearance and the planner found a path.

    The clearance is the exact distance from the way's centre line to the nearest occupied
    cell; at or above the circumscribed radius, the body can stand anywhere on the way at any
    heading.
    """
    if course.way is None or course.way.shape[0] < 2:
        return "no way"
    if course.way_clearance < footprint.circumscribed_radius:
        return (f"the way's clearance {course.way_clearance:.3f} m is under the body's "
                f"circumscribed radius {footprint.circumscribed_radius:.3f} m")
    ends = (course.way[0], course.way[-1])
    if (math.hypot(ends[0][0] - course.start.x, ends[0][1] - course.start.y) > 1e-9
            or math.hypot(ends[1][0] - course.goal.x, ends[1][1] - course.goal.y) > 1e-9):
        return "the way does not join start and goal"
    least = clearance_along(course.world.floors[0].map, course.way)
    if least < course.way_clearance:
        return f"the way passes {least:.3f} m from an obstacle (< {course.way_clearance:.3f} m)"
    if course.path.points.shape[0] == 0:
        return "empty path"
    return None


def _frame(footprint: Footprint, spec: ClutterSpec, rng: np.random.Generator) -> _Frame:
    res = RESOLUTION
    length = spec.span + 3.0
    start = Pose2D(WALL + 1.5, WALL + 0.5 * spec.width, 0.0)
    goal = Pose2D(start.x + spec.span, start.y, 0.0)
    clearance = max(spec.way_clearance, footprint.circumscribed_radius + spec.lane_margin)
    # Barriers spread evenly over the field, more when dense. The way passes each one on its
    # own side, 1.6 m or more off the centre line, the sides alternating: it winds across the
    # box, and the barriers' gates on the straight line look much shorter to a planner.
    x0, x1 = start.x + 1.5, goal.x - 1.5
    # No more than leaves the way its level runs past each (a short span takes fewer).
    fits = max(int((x1 - x0) // (WAY_BEFORE + WAY_AFTER + 0.2)), 1)
    count = min(1 + int(round((BARRIERS - 1) * spec.density)), fits)
    pitch = (x1 - x0) / count
    # A little jitter, never so much that the way's level runs overlap.
    barriers = tuple(float(x0 + (i + 0.5) * pitch + rng.uniform(-0.04, 0.04) * pitch)
                     for i in range(count))
    room = 0.5 * spec.width - clearance - 0.25
    lo = min(WAY_OFFSET, room)
    side = 1.0 if rng.random() < 0.5 else -1.0
    points = [(start.x, start.y)]
    for x in barriers:
        y = start.y + side * float(rng.uniform(lo, room))
        points += [(x - WAY_BEFORE, y), (x + WAY_AFTER, y)]
        side = -side
    points.append((goal.x, goal.y))
    r_cells = spec.post_radius / res
    span = int(math.floor(r_cells))
    stamp = tuple((dx, dy) for dx in range(-span, span + 1) for dy in range(-span, span + 1)
                  if math.hypot(dx, dy) <= r_cells or (dx, dy) == (0, 0))
    arm = max(dx for dx, _ in stamp)
    reach = max(math.hypot(dx, dy) for dx, dy in stamp) * res + res / math.sqrt(2.0)
    grid = box_cells(length, spec.width, res)
    return _Frame(
        footprint=footprint, spec=spec, start=start, goal=goal,
        way=np.asarray(points, dtype=np.float64), barriers=barriers, clearance=clearance,
        stamp=stamp, arm=arm,
        reach=reach, step=max(1, round(spec.pitch / res)), nx=grid.shape[1], ny=grid.shape[0],
    )


def _barriers(
    frame: _Frame,
    rng: np.random.Generator,
    posts: set[Cell],
    structures: list[Structure],
    openings: list[tuple[Cell, Cell]],
) -> list[tuple[float, float]]:
    """Build the barriers (gates and chicanes); their x bands [m], kept from other structures."""
    lo, hi = CHICANE_ODDS
    odds = lo + (hi - lo) * frame.spec.density
    bands = []
    for x in frame.barriers:
        chicane = rng.random() < odds
        bands.append((x, _barrier(frame, rng, x, chicane, posts, structures, openings)))
    return bands


def _barrier(
    frame: _Frame,
    rng: np.random.Generator,
    x: float,
    chicane: bool,
    posts: set[Cell],
    structures: list[Structure],
    openings: list[tuple[Cell, Cell]],
) -> float:
    """One barrier at ``x`` [m] across the box; where it ends along x [m]."""
    ix, iy_line = frame.cell(x, frame.start.y)
    width = frame.tight_width(rng)
    # The gate's free cells are [lo, lo + width); the straight line crosses them.
    lo = iy_line - int(rng.integers(1, width))
    added = _gated_wall(frame, ix, lo, width, posts)
    openings.append(((ix, lo + width // 2), (0, 1)))
    kind, end_ix = "gate", ix
    if chicane:
        depth = frame.tight_width(rng)
        ix2 = ix + depth + 2 * frame.arm + 1
        width2 = frame.tight_width(rng)
        shift = int(math.ceil(float(rng.uniform(*CHICANE_SHIFT)) / RESOLUTION))
        # The second gap on the side of the line away from the way, which is near there.
        way_y = float(np.interp(x, frame.way[:, 0], frame.way[:, 1]))
        lo2 = lo + width + shift if way_y < frame.start.y else lo - shift - width2
        added += _gated_wall(frame, ix2, lo2, width2, posts)
        openings.append(((ix2, lo2 + width2 // 2), (0, 1)))
        # The corridor between the walls, measured across it where both walls have a post
        # (its narrowest), nearest the first gate.
        rows = sorted((iy for jx, iy in posts if jx == ix and (ix2, iy) in posts),
                      key=lambda iy: abs(iy - lo))
        if rows:
            openings.append(((ix + frame.arm + 1 + depth // 2, rows[0]), (1, 0)))
        kind, end_ix = "chicane", ix2
    gx, gy = frame.centre((ix, lo + width // 2))
    structures.append(Structure(kind, gx, gy, 0.0, added))
    return frame.centre((end_ix, 0))[0]


def _gated_wall(frame: _Frame, ix: int, lo: int, width: int, posts: set[Cell]) -> int:
    """A wall of posts along column ``ix`` from side wall to side wall, open at the gate (rows
    ``lo`` to ``lo + width - 1``) and wherever the way passes; how many posts it added."""
    w = round(WALL / RESOLUTION)
    # End posts just outside the gate, so that exactly ``width`` rows stay free.
    rows = [*range(lo - frame.arm - 1, w - 1, -frame.step),
            *range(lo + width + frame.arm, frame.ny - w, frame.step)]
    cells = [(ix, iy) for iy in sorted(rows)]
    keep = frame.clear_of_way(cells)
    new = [c for c, ok in zip(cells, keep, strict=True) if ok and c not in posts]
    posts.update(new)
    return len(new)


def _line_pockets(
    frame: _Frame,
    rng: np.random.Generator,
    posts: set[Cell],
    structures: list[Structure],
    bands: list[tuple[float, float]],
) -> None:
    """Pockets on the straight line, open towards the start (more likely when dense)."""
    if rng.random() >= 0.3 + 0.5 * frame.spec.density:
        return
    for _ in range(20):
        x = float(rng.uniform(frame.start.x + 1.5, frame.goal.x - 1.5))
        if _in_bands(x, bands, 1.5):
            continue
        cells, anchor = _pocket(frame, rng, frame.cell(x, frame.start.y))
        if _place(frame, cells, posts):
            structures.append(Structure("pocket", *frame.centre(anchor), math.pi, len(cells)))
            return


def _random_structures(
    frame: _Frame,
    rng: np.random.Generator,
    posts: set[Cell],
    structures: list[Structure],
    openings: list[tuple[Cell, Cell]],
    bands: list[tuple[float, float]],
) -> None:
    """Walls, hooks, pockets, boxes and slots thrown between the barriers, clear of the way."""
    spec = frame.spec
    wanted = int(round((6.0 + 18.0 * spec.density) * spec.span / 10.0))
    placed = 0
    w = WALL
    for _ in range(10 * wanted):
        if placed == wanted:
            break
        x = float(rng.uniform(frame.start.x + 0.8, frame.goal.x - 0.8))
        if rng.random() < 0.5:
            y = frame.start.y + float(rng.uniform(-NEAR_LINE, NEAR_LINE))
        else:
            y = float(rng.uniform(w + 0.1, w + spec.width - 0.1))
        if _in_bands(x, bands, BAND):
            continue
        kind = str(rng.choice(STRUCTURE_KINDS, p=KIND_WEIGHTS))
        at = frame.cell(x, y)
        facing = 0.0
        opening: tuple[Cell, Cell] | None = None
        if kind == "wall":
            axis = _AXES[int(rng.integers(4))]
            cells = _run(frame, at, axis, int(rng.integers(5, 21)))
            facing = math.atan2(axis[1], axis[0])
        elif kind == "hook":
            cells, facing = _hook(frame, rng, at)
        elif kind == "pocket":
            cells, anchor = _pocket(frame, rng, at)
            at, facing = anchor, math.pi
        elif kind == "box":
            k = int(rng.integers(1, 4))
            cells = [(at[0] + i * frame.step, at[1] + j * frame.step)
                     for i in range(k) for j in range(k)]
        else:
            cells, opening, facing = _slot(frame, rng, at)
        # Openings stay as made: nothing new in an old one, and a new one over nothing old.
        if _blocks_opening(frame, cells, openings) or (
                opening is not None and _blocks_opening(frame, sorted(posts), [opening])):
            continue
        if not _place(frame, cells, posts):
            continue
        structures.append(Structure(kind, *frame.centre(at), facing, len(cells)))
        if opening is not None:
            openings.append(opening)
        placed += 1


def _run(frame: _Frame, at: Cell, axis: Cell, n: int) -> list[Cell]:
    """``n`` posts from ``at`` along ``axis``, a lattice step apart (touching: a wall)."""
    return [(at[0] + k * frame.step * axis[0], at[1] + k * frame.step * axis[1])
            for k in range(n)]


def _hook(frame: _Frame, rng: np.random.Generator, at: Cell) -> tuple[list[Cell], float]:
    """An L (or, half the time, a J: an L with a short return), at any of 4 x 2 poses."""
    i = int(rng.integers(4))
    a = _AXES[i]
    b = _AXES[(i + (1 if rng.random() < 0.5 else 3)) % 4]
    first = _run(frame, at, a, int(rng.integers(6, 16)))
    second = _run(frame, first[-1], b, int(rng.integers(4, 11)))
    cells = first + second[1:]
    if rng.random() < 0.5:
        back = (-a[0], -a[1])
        cells += _run(frame, second[-1], back, int(rng.integers(3, 6)))[1:]
    return cells, math.atan2(a[1], a[0])


def _pocket(frame: _Frame, rng: np.random.Generator, at: Cell) -> tuple[list[Cell], Cell]:
    """A U open towards the start (-x), its back at ``at``; its cells and the middle of its
    open side. Inside it is from a little over the body's width to well over its diagonal."""
    lo = 2.0 * frame.footprint.inscribed_radius + 0.05
    hi = 2.0 * frame.footprint.circumscribed_radius + 0.3
    inner = int(math.ceil(float(rng.uniform(lo, hi)) / RESOLUTION))
    depth = int(rng.integers(6, 13))  # posts along each arm
    # Arm rows so that ``inner`` rows stay free between the arms' posts.
    bottom = at[1] - (inner + 2 * frame.arm + 1) // 2
    top = bottom + inner + 2 * frame.arm + 1
    back = [(at[0], iy) for iy in range(bottom, top + 1, frame.step)]
    if back[-1][1] != top:
        back.append((at[0], top))
    arms = (_run(frame, (at[0], bottom), (-1, 0), depth)[1:]
            + _run(frame, (at[0], top), (-1, 0), depth)[1:])
    mouth = (at[0] - (depth - 1) * frame.step, (bottom + top) // 2)
    return back + arms, mouth


def _slot(
    frame: _Frame, rng: np.random.Generator, at: Cell
) -> tuple[list[Cell], tuple[Cell, Cell], float]:
    """Two parallel walls with a tight width between them; cells, opening, direction [rad]."""
    i = int(rng.integers(2))
    a = _AXES[i]
    across = _AXES[1 - i]
    n = int(rng.integers(6, 13))
    width = frame.tight_width(rng)
    offset = width + 2 * frame.arm + 1
    other = (at[0] + offset * across[0], at[1] + offset * across[1])
    cells = _run(frame, at, a, n) + _run(frame, other, a, n)
    mid = n // 2 * frame.step
    centre = (at[0] + mid * a[0] + (frame.arm + 1 + width // 2) * across[0],
              at[1] + mid * a[1] + (frame.arm + 1 + width // 2) * across[1])
    return cells, (centre, across), math.atan2(a[1], a[0])


def _place(frame: _Frame, cells: list[Cell], posts: set[Cell]) -> bool:
    """Add a whole structure if it stands in the box and leaves the way clear; else nothing."""
    if not frame.inside(cells) or not bool(np.all(frame.clear_of_way(cells))):
        return False
    posts.update(cells)
    return True


def _blocks_opening(frame: _Frame, cells: list[Cell], openings: list[tuple[Cell, Cell]]) -> bool:
    """Would a post stand in or next to an opening already made (so it stays as measured)?"""
    if not openings or not cells:
        return False
    c = np.asarray(cells, dtype=np.float64)
    o = np.asarray([centre for centre, _ in openings], dtype=np.float64)
    d = np.hypot(c[:, None, 0] - o[None, :, 0], c[:, None, 1] - o[None, :, 1]) * RESOLUTION
    widest = 2.0 * frame.footprint.circumscribed_radius + 0.1
    return bool(np.any(d < 0.5 * widest + frame.reach + OPENING_ROOM))


def _in_bands(x: float, bands: list[tuple[float, float]], margin: float) -> bool:
    return any(a - margin <= x <= b + margin for a, b in bands)


def _rasterize(frame: _Frame, posts: set[Cell]) -> Map:
    occupied = box_cells(frame.spec.span + 3.0, frame.spec.width, RESOLUTION)
    if posts:
        c = np.asarray(sorted(posts), dtype=np.int64)
        for dx, dy in frame.stamp:
            ix = np.clip(c[:, 0] + dx, 0, frame.nx - 1)
            iy = np.clip(c[:, 1] + dy, 0, frame.ny - 1)
            occupied[iy, ix] = True
    return Map.from_occupied(occupied, resolution=RESOLUTION)


def _measure(frame: _Frame, grid: Map, centre: Cell, axis: Cell) -> Gap | None:
    """The free run through ``centre`` along ``axis`` on the drawn grid, or ``None`` if a
    later structure filled the opening."""
    occupied = grid.occupied()
    ix, iy = centre
    if occupied[iy, ix]:
        return None
    ends = []
    for sign in (-1, 1):
        k = 0
        while True:
            jx, jy = ix + sign * (k + 1) * axis[0], iy + sign * (k + 1) * axis[1]
            if not (0 <= jx < frame.nx and 0 <= jy < frame.ny) or occupied[jy, jx]:
                break
            k += 1
        ends.append(k)
    free = ends[0] + ends[1] + 1
    res = RESOLUTION
    # The opening's free segment, from the face of one bounding cell to the other's.
    a = np.array(frame.centre((ix - ends[0] * axis[0], iy - ends[0] * axis[1])))
    b = np.array(frame.centre((ix + ends[1] * axis[0], iy + ends[1] * axis[1])))
    unit = np.array(axis, dtype=np.float64)
    a, b = a - 0.5 * res * unit, b + 0.5 * res * unit
    s = np.array([frame.start.x, frame.start.y])
    g = np.array([frame.goal.x, frame.goal.y])
    x, y = frame.centre(centre)
    return Gap(x, y, free * res, math.atan2(axis[1], axis[0]), _segments_cross(a, b, s, g))


def _segments_cross(
    a: npt.NDArray[np.float64], b: npt.NDArray[np.float64],
    c: npt.NDArray[np.float64], d: npt.NDArray[np.float64],
) -> bool:
    def orient(p: npt.NDArray[np.float64], q: npt.NDArray[np.float64],
               r: npt.NDArray[np.float64]) -> float:
        return float((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]))

    return (orient(a, b, c) * orient(a, b, d) <= 0.0
            and orient(c, d, a) * orient(c, d, b) <= 0.0)


def _distances_to_polyline(
    pts: npt.NDArray[np.float64], line: npt.NDArray[np.float64]
) -> npt.NDArray[np.float64]:
    """Distance [m] from each point (N, 2) to the polyline (M, 2)."""
    a, b = line[:-1], line[1:]
    d = b - a
    den = np.maximum(np.sum(d * d, axis=1), 1e-12)
    rel = pts[:, None, :] - a[None, :, :]
    t = np.clip(np.sum(rel * d[None, :, :], axis=2) / den[None, :], 0.0, 1.0)
    near = a[None, :, :] + t[:, :, None] * d[None, :, :]
    return np.asarray(np.min(np.hypot(*(pts[:, None, :] - near).transpose(2, 0, 1)), axis=1))
