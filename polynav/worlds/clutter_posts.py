"""The ``posts`` kind of clutter course: a field of thin posts thrown at random.

Issue 18's course. Drawn from a seed and a *density* between 0 (sparse) and 1 (barely passable):

1. A walled box, ``span + 3`` x ``width`` inside, start 1.5 m from one end wall and the goal
   ``span`` [m] further along the box's centre line.
2. A *lane* from start to goal: a polyline through random waypoints across the field, kept clear
   of posts by the body's circumscribed radius plus ``lane_margin``. This is the construction's
   guarantee that the footprint can get through whatever its heading.
3. Posts (disks of ``post_radius`` [m], a few cells) thrown at random into the field between
   the start and goal areas; a post is kept only if it leaves the lane clear and every gap to a
   post or wall already placed is at least ``min_gap`` [m]. ``min_gap`` falls with the density
   from three body widths to one body width plus ``tight_margin``: at density 1 gaps are barely
   wider than the robot, so a route may go through them only heading along.
4. The guarantee is *checked* (:func:`check`): the grid planner must find a path on the static
   costmap inflated by the body's inscribed radius, and the body placed along that path, facing
   along it, must touch no post.
"""

from __future__ import annotations

import logging
import math

import numpy as np
import numpy.typing as npt

from polynav import footprint as body
from polynav.errors import PolynavError
from polynav.footprint import Footprint
from polynav.geometry import Pose2D
from polynav.maps.costmap import Costmap
from polynav.maps.map import Map
from polynav.planning.grid_planner import GridPlanner, GridPlannerConfig
from polynav.planning.path import Path
from polynav.worlds.clutter_course import (
    RESOLUTION,
    WALL,
    ClutterCourse,
    ClutterSpec,
    box_cells,
    distance_to_polyline,
    one_floor_world,
    static_config,
)

log = logging.getLogger(__name__)


def min_gap_for(footprint: Footprint, spec: ClutterSpec) -> float:
    """Smallest gap [m] between posts at ``spec.density``: from three body widths down to one
    body width plus ``tight_margin``."""
    width = 2.0 * footprint.inscribed_radius
    tight = width + spec.tight_margin
    return tight + (1.0 - spec.density) * 2.0 * width


def check(course: ClutterCourse, footprint: Footprint) -> str | None:
    """``None`` if the body fits along the course's path facing along it, else why not."""
    floor = course.world.floors[0]
    static = Costmap.from_map(floor.map, static_config(footprint))
    poses = path_poses(course.path)
    hit = body.first_collision(footprint, static, poses)
    if hit is not None:
        p = poses[hit]
        return f"the body touches a post at ({p[0]:.2f}, {p[1]:.2f})"
    if course.path.points.shape[0] == 0:
        return "empty path"
    return None


def path_poses(path: Path) -> npt.NDArray[np.float64]:
    """Poses (N, 3) half a cell apart along ``path``, each facing along its segment."""
    pts = path.points
    if pts.shape[0] < 2:
        return np.zeros((0, 3))
    rows = []
    for a, b in zip(pts[:-1], pts[1:], strict=True):
        d = b - a
        n = max(int(math.ceil(float(np.hypot(*d)) / (0.5 * RESOLUTION))), 1)
        t = np.linspace(0.0, 1.0, n, endpoint=False)
        seg = a + t[:, None] * d
        rows.append(np.column_stack((seg, np.full(n, math.atan2(d[1], d[0])))))
    last = pts[-1] - pts[-2]
    rows.append(np.array([[pts[-1, 0], pts[-1, 1], math.atan2(last[1], last[0])]]))
    return np.vstack(rows)


def draw_once(
    footprint: Footprint, spec: ClutterSpec, rng: np.random.Generator, seed: int
) -> ClutterCourse:
    """One unchecked draw of a ``posts`` course (see the module docstring)."""
    res = RESOLUTION
    length = spec.span + 3.0
    start = Pose2D(WALL + 1.5, WALL + 0.5 * spec.width, 0.0)
    goal = Pose2D(start.x + spec.span, start.y, 0.0)
    # The lane: through one random waypoint every ~2 m across the field.
    field_x0, field_x1 = start.x + 1.0, goal.x - 1.0
    half = footprint.circumscribed_radius + spec.lane_margin
    n_mid = max(int(spec.span // 2.0) - 1, 1)
    xs = np.linspace(field_x0, field_x1, n_mid + 2)[1:-1]
    y_room = 0.5 * spec.width - half - 0.2
    ys = start.y + rng.uniform(-y_room, y_room, size=n_mid)
    lane = np.vstack([[start.x, start.y], [field_x0, start.y], np.column_stack((xs, ys)),
                      [field_x1, goal.y], [goal.x, goal.y]])
    min_gap = min_gap_for(footprint, spec)
    posts: list[tuple[float, float]] = []
    r = spec.post_radius
    area = (field_x1 - field_x0) * spec.width
    for _ in range(int(spec.attempts * area)):
        px = float(rng.uniform(field_x0, field_x1))
        py = float(rng.uniform(WALL + r, WALL + spec.width - r))
        if distance_to_polyline(px, py, lane) < half + r:
            continue
        wall_gap = min(py - WALL, WALL + spec.width - py) - r
        if wall_gap < min_gap and wall_gap > 0.0:
            continue
        if posts:
            p = np.asarray(posts)
            if float(np.min(np.hypot(p[:, 0] - px, p[:, 1] - py))) - 2.0 * r < min_gap:
                continue
        posts.append((px, py))
    post_array = np.asarray(posts, dtype=np.float64).reshape(-1, 2)
    grid = _rasterize(length, spec.width, post_array, r, res)
    static = Costmap.from_map(grid, static_config(footprint))
    try:
        path = GridPlanner(GridPlannerConfig()).plan(static, start, goal)
    except PolynavError as exc:
        path = Path(np.zeros((0, 2)))
        log.warning("clutter course %d: no path on the static map: %s", seed, exc)
    return ClutterCourse(one_floor_world(grid, start, seed), start, goal, post_array, min_gap,
                         path, kind="posts")


def _rasterize(
    length: float, width: float, posts: npt.NDArray[np.float64], radius: float, res: float
) -> Map:
    occupied = box_cells(length, width, res)
    ny, nx = occupied.shape
    iy, ix = np.mgrid[0:ny, 0:nx]
    cx = (ix + 0.5) * res
    cy = (iy + 0.5) * res
    # A cell is a post's if the post's disk covers its centre, or if it holds the post's centre
    # (a post thinner than a cell still exists).
    for px, py in posts:
        occupied |= np.hypot(cx - px, cy - py) <= radius
        occupied[int(py // res), int(px // res)] = True
    return Map.from_occupied(occupied, resolution=res)
