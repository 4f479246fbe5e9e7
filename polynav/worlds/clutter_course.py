"""What every kind of clutter course shares: the spec, the drawn course, and its grid pieces.

A clutter course (:mod:`polynav.worlds.clutter`) is a walled box with obstacles between a start
and a goal ``span`` [m] apart. Each *kind* draws the obstacles its own way (``posts``:
:mod:`polynav.worlds.clutter_posts`; ``lattice``: :mod:`polynav.worlds.clutter_lattice`), but
they all fill the same :class:`ClutterSpec` and :class:`ClutterCourse`, on the same 0.05 m grid
inside the same 0.2 m walls, so the benchmark and the tests take any kind alike.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
from scipy import ndimage

from polynav.errors import InvalidRequest, PolynavError
from polynav.footprint import Footprint
from polynav.geometry import Pose2D
from polynav.maps.costmap import CostmapConfig
from polynav.maps.map import Map
from polynav.planning.path import Path
from polynav.worlds.world import World, WorldFloor

RESOLUTION = 0.05  # [m]
WALL = 0.2  # [m] thickness of the box's walls


@dataclass(frozen=True, slots=True)
class ClutterSpec:
    """How a course is drawn (SI units; see the kinds' module docstrings).

    Attributes:
        kind: the course kind, a name in :data:`polynav.worlds.clutter.KINDS`.
        density: 0 (sparse) .. 1 (barely passable).
        span: straight-line distance from start to goal [m].
        width: inside width of the box [m].
        post_radius: radius of every post [m].
        lane_margin: clearance [m] of the guaranteed lane beyond the body's circumscribed radius.
        tight_margin: at density 1, gaps are the body's width plus this [m] (``posts``).
        attempts: posts thrown per square metre of field (``posts``; most are rejected when
            dense).
        pitch: spacing [m] of the lattice the posts of one structure stand on (``lattice``);
            at most twice ``post_radius`` so that neighbours touch and a run is a wall.
        way_clearance: the least clearance [m] of the guaranteed way's centre line
            (``lattice``); the way keeps ``max(way_clearance, circumscribed radius +
            lane_margin)``.
    """

    kind: str = "posts"
    density: float = 0.5
    span: float = 10.0
    width: float = 6.0
    post_radius: float = 0.06
    lane_margin: float = 0.1
    tight_margin: float = 0.1
    attempts: float = 40.0
    pitch: float = 0.1
    way_clearance: float = 0.45

    def __post_init__(self) -> None:
        if not 0.0 <= self.density <= 1.0:
            raise InvalidRequest("density", f"must be within 0..1, got {self.density}")
        for name in ("span", "width", "post_radius", "attempts", "pitch"):
            if not getattr(self, name) > 0.0:
                raise InvalidRequest(name, f"must be > 0, got {getattr(self, name)}")
        for name in ("lane_margin", "tight_margin", "way_clearance"):
            if not getattr(self, name) >= 0.0:
                raise InvalidRequest(name, f"must be >= 0, got {getattr(self, name)}")
        if self.pitch > 2.0 * self.post_radius:
            raise InvalidRequest(
                "pitch", f"must be at most 2 x post_radius ({2.0 * self.post_radius:g}) so that "
                f"neighbouring posts touch, got {self.pitch}"
            )


@dataclass(frozen=True, slots=True)
class Structure:
    """One obstacle a generator placed, for tests and for a reader of a failed course.

    Attributes:
        kind: ``wall``, ``hook``, ``pocket``, ``box``, ``gate`` or ``chicane``.
        x: anchor of the structure [m] (a pocket's: the middle of its open side).
        y: [m].
        facing: direction [rad] the structure faces: for a pocket, the way its open side
            looks (pi: towards the start); for a gate or a chicane, the way through it (0:
            towards the goal); for the others, the direction their first run of posts goes.
        posts: how many posts it has.
    """

    kind: str
    x: float
    y: float
    facing: float
    posts: int


@dataclass(frozen=True, slots=True)
class Gap:
    """A free opening a generator made on purpose, measured on the drawn grid.

    Attributes:
        x: centre of the opening [m].
        y: [m].
        width: free width [m] across the opening on the grid: the free cells between the two
            obstacle cells that bound it, times the resolution.
        across: direction [rad] along which ``width`` is measured.
        on_line: the straight line from start to goal passes through the opening.
    """

    x: float
    y: float
    width: float
    across: float
    on_line: bool


@dataclass(frozen=True, slots=True, eq=False)
class ClutterCourse:
    """A drawn course: the world, where the robot starts and where it goes, and the checked path.

    ``path`` is the planner's path on the static map (see :attr:`optimal_length`);
    ``optimal_length`` its length [m] (the benchmark's yardstick at top speed). ``min_gap`` is
    the narrowest gap [m] the generator meant to leave (``posts``: between any two posts;
    ``lattice``: the narrowest of ``gaps``). ``way`` is the kind's checked feasible route when
    it keeps one apart from ``path`` (``lattice``: a polyline whose centre line stays
    ``way_clearance`` [m] from every obstacle), else ``None``.
    """

    world: World
    start: Pose2D
    goal: Pose2D
    posts: npt.NDArray[np.float64]
    min_gap: float
    path: Path
    kind: str = "posts"
    structures: tuple[Structure, ...] = ()
    gaps: tuple[Gap, ...] = ()
    way: npt.NDArray[np.float64] | None = None
    way_clearance: float = 0.0

    @property
    def optimal_length(self) -> float:
        """Length [m] of ``path``: the benchmark's yardstick.

        ``posts`` keeps issue 18's plan on the map inflated by the inscribed radius with the
        planner's default cost weight (a route the body can drive facing along it, checked).
        ``lattice`` plans with the body's own planner and no cost penalty: the shortest route
        the body can drive, up to the lattice's 16 headings (a disk: the grid's shortest
        path). Time spent turning in place is not in it.
        """
        return self.path.length


class CourseError(PolynavError):
    """No course with a checked feasible path could be drawn from this seed."""


def static_config(footprint: Footprint) -> CostmapConfig:
    """The static costmap the courses are planned and checked on: inflated by the inscribed
    radius, no live obstacles."""
    inscribed = footprint.inscribed_radius
    return CostmapConfig(
        robot_radius=inscribed,
        inflation_radius=max(inscribed, footprint.circumscribed_radius) + 0.3,
        obstacle_layer=False,
    )


def box_cells(length: float, width: float, res: float) -> npt.NDArray[np.bool_]:
    """Occupancy ``[iy, ix]`` of the empty walled box: ``length`` x ``width`` [m] inside."""
    nx = round((length + 2 * WALL) / res)
    ny = round((width + 2 * WALL) / res)
    w = round(WALL / res)
    occupied = np.ones((ny, nx), dtype=bool)
    occupied[w:ny - w, w:nx - w] = False
    return occupied


def one_floor_world(grid: Map, start: Pose2D, seed: int) -> World:
    """The one-floor world of a course drawn from ``seed``."""
    floor = WorldFloor(name="floor1", level=1, map_name=f"clutter-{seed}", map=grid, points=(),
                       lift=None, people=())
    return World(name=f"clutter-{seed}", floors=(floor,), start_floor="floor1",
                 start_pose=start)


def distance_to_polyline(x: float, y: float, line: npt.NDArray[np.float64]) -> float:
    """Distance [m] from (x, y) to the polyline ``line`` (N, 2)."""
    a, b = line[:-1], line[1:]
    d = b - a
    den = np.maximum(np.sum(d * d, axis=1), 1e-12)
    t = np.clip(((x - a[:, 0]) * d[:, 0] + (y - a[:, 1]) * d[:, 1]) / den, 0.0, 1.0)
    px = a[:, 0] + t * d[:, 0] - x
    py = a[:, 1] + t * d[:, 1] - y
    return float(np.min(np.hypot(px, py)))


def sample_polyline(line: npt.NDArray[np.float64], step: float) -> npt.NDArray[np.float64]:
    """Points (M, 2) along ``line`` no more than ``step`` [m] apart, both ends included."""
    rows = []
    for a, b in zip(line[:-1], line[1:], strict=True):
        n = max(int(math.ceil(float(np.hypot(*(b - a))) / step)), 1)
        t = np.linspace(0.0, 1.0, n, endpoint=False)
        rows.append(a + t[:, None] * (b - a))
    rows.append(line[-1:])
    return np.vstack(rows)


def clearance_along(
    grid: Map, line: npt.NDArray[np.float64], *, step: float = 0.5 * RESOLUTION
) -> float:
    """Least distance [m] from the polyline ``line`` to any occupied cell of ``grid``.

    A cell is the full square it covers. The distance is sampled every ``step`` [m] and the
    half step it may fall between samples is taken off, so the figure is never too high.
    """
    info = grid.info
    res = info.resolution
    occupied = grid.occupied()
    # Only cells on an obstacle's rim can be nearest to a point in free space.
    inner = ndimage.binary_erosion(occupied, structure=np.ones((3, 3), dtype=bool),
                                   border_value=True)
    iy, ix = np.nonzero(occupied & ~inner)
    # Cell centres in the world frame (the courses' maps are axis-aligned at the origin).
    cx = info.origin.x + (ix + 0.5) * res
    cy = info.origin.y + (iy + 0.5) * res
    pts = sample_polyline(line, step)
    half = 0.5 * res
    least = math.inf
    for chunk in np.array_split(pts, max(1, pts.shape[0] // 64)):
        dx = np.maximum(np.abs(chunk[:, 0, None] - cx[None, :]) - half, 0.0)
        dy = np.maximum(np.abs(chunk[:, 1, None] - cy[None, :]) - half, 0.0)
        least = min(least, float(np.min(np.hypot(dx, dy))))
    return least - 0.5 * step
