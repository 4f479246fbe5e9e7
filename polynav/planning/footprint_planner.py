"""The planner for a body that is not a disk: the grid route when the body can drive it, else a
lattice route over position and heading (:mod:`polynav.planning.lattice`).

A grid planner inflating by the inscribed radius plans for a disk the size of the body's
narrowest width. A rectangle following such a route stops before any gap between its width and
its diagonal that the route enters turning, and every re-plan sends it into the same gap. So
this planner first plans on the grid (fast, and the route a disk would take), then *checks* that
route with the footprint at the headings the robot will have along it, turns in place at its
corners included (:func:`route_poses`). A route the body can drive is returned as it is; only
when the check fails does the lattice search run, in a window 4 m round the route (then 12 m),
and its shortened route is returned. A long route (over 30 m) is first repaired only round the
stretch the body cannot drive, 5 m either side, and spliced. Windows are capped in states (the
bound on memory); a route too long to search round keeps the grid route, as before this
planner, and the controller and the closed passages deal with it. The route must leave the body
room all round (``LatticeConfig.footprint_paddings``, most room first: the controller drives
faster with room to spare); where no route leaves any, the search runs again for the body as it
is; where the body fits the grid route facing
along it but at no lattice cell and heading, the grid route is returned. When no heading lets
the body through in any window searched, :class:`NoBodyRoute` (a :class:`NoPath`) carries the
grid route and where the body first touches along it: the navigator fails the goal at once if
that is the building, and follows the grid route if it is only the lidar's marks (a person's
trail), which pass.

The grid planner's rules (typed errors for start, goal and tolerance) apply unchanged: the grid
plan comes first and decides the end point. A disk needs none of this, and keeps the grid
planner alone (:func:`~polynav.planning.registry.for_footprint`).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
from scipy import ndimage

from polynav import footprint as body
from polynav.errors import ConfigError
from polynav.footprint import Footprint
from polynav.geometry import Pose2D
from polynav.maps import costs as cost_values
from polynav.maps.interface import CostGrid
from polynav.maps.map import MapInfo
from polynav.planning import lattice, smoothing
from polynav.planning.errors import NoBodyRoute, PlanningError
from polynav.planning.grid_planner import GridPlanner, GridPlannerConfig
from polynav.planning.grid_search import step_multipliers
from polynav.planning.path import Path

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True)
class LatticeConfig:
    """How the lattice search runs (SI units).

    Attributes:
        turn_cost: price of turning in place [m per rad]: a quarter turn costs as much as
            driving ``turn_cost * pi / 2`` metres, so the route does not wriggle.
        window_margins: the search runs in a window this far [m] beyond the stretch's box,
            then in the next wider one if that holds no way.
        max_states: a window of more states than this (cells x 16 headings) is not searched:
            the bound on memory (about 10 bytes a state).
        max_expansions: the search gives up after this many states (a bound on time).
        max_leg: the shortening tries straight legs up to this long [m].
        local_repair_over: a route longer than this [m] is repaired only round the stretch
            the body cannot drive, ``repair_margin`` [m] either side of it, when that works.
        footprint_paddings: the route must leave the body this much room [m] all round
            (Nav2's ``footprint_padding``), for control and localization to err in: the first
            padding in the list that leaves a route (most room first; the controller drives
            faster with more room) ...
        exact_near_start: ... except within this distance [m] of where the robot stands,
            where it is checked as it is (it may not have that room where it stands).
    """

    turn_cost: float = 0.3
    window_margins: tuple[float, ...] = (4.0, 12.0)
    max_states: int = 12_000_000
    max_expansions: int = 3_000_000
    max_leg: float = 4.0
    local_repair_over: float = 30.0
    repair_margin: float = 5.0
    footprint_paddings: tuple[float, ...] = (0.05,)
    exact_near_start: float = 0.5

    def __post_init__(self) -> None:
        if not self.window_margins or any(not (math.isfinite(m) and m >= 0.0)
                                          for m in self.window_margins):
            raise ConfigError("planner.lattice.window_margins", "must be finite values >= 0")
        if self.max_states < 1:
            raise ConfigError("planner.lattice.max_states", "must be >= 1")
        if not self.footprint_paddings or any(not (math.isfinite(p) and p >= 0.0)
                                              for p in self.footprint_paddings):
            raise ConfigError("planner.lattice.footprint_paddings",
                              "must be one or more finite values >= 0")
        for key in ("turn_cost", "max_leg", "local_repair_over", "repair_margin",
                    "exact_near_start"):
            value = getattr(self, key)
            if not (math.isfinite(value) and value >= 0.0):
                raise ConfigError(f"planner.lattice.{key}", f"must be finite and >= 0, got {value}")
        if self.max_expansions < 1:
            raise ConfigError("planner.lattice.max_expansions", "must be >= 1")


def route_poses(
    points: npt.NDArray[np.float64],
    footprint: Footprint,
    resolution: float,
    start_theta: float | None = None,
) -> npt.NDArray[np.float64]:
    """Poses (N, 3) of a robot driving the polyline facing along it, turning in place at its
    corners: half-cell steps along each leg, :meth:`Footprint.rotation_step` through each turn,
    the first one from ``start_theta`` [rad] onto the first leg included when given."""
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    deltas = np.diff(pts, axis=0)
    lengths = np.hypot(deltas[:, 0], deltas[:, 1])
    keep = lengths > 1e-9
    pts = np.vstack([pts[:1], pts[1:][keep]])
    deltas, lengths = deltas[keep], lengths[keep]
    if lengths.size == 0:
        return np.zeros((0, 3))
    headings = np.arctan2(deltas[:, 1], deltas[:, 0])
    step = 0.5 * resolution
    turn_step = footprint.rotation_step(resolution)
    rows: list[npt.NDArray[np.float64]] = []
    if start_theta is not None:
        # The robot's own pose first: what it touches there is what a check may ignore.
        rows.append(np.array([[pts[0, 0], pts[0, 1], start_theta]]))
        headings = np.concatenate([[start_theta], headings])
        pts = np.vstack([pts[:1], pts])
    first = 0 if start_theta is None else 1
    for k in range(first, headings.size):
        if k > 0:
            turn = math.remainder(float(headings[k] - headings[k - 1]), 2.0 * math.pi)
            n = int(math.ceil(abs(turn) / turn_step))
            if n > 1:
                angles = headings[k - 1] + turn * np.arange(1, n) / n
                rows.append(np.column_stack(
                    (np.full(n - 1, pts[k, 0]), np.full(n - 1, pts[k, 1]), angles)))
        leg = k - first
        n = max(int(math.ceil(lengths[leg] / step)), 1)
        t = np.arange(n + 1) / n
        rows.append(np.column_stack((pts[k, 0] + t * deltas[leg, 0],
                                     pts[k, 1] + t * deltas[leg, 1],
                                     np.full(n + 1, headings[k]))))
    return np.vstack(rows)


def drivable(
    path: Path, footprint: Footprint, costmap: CostGrid, start_theta: float | None = None
) -> bool:
    """Can the body drive ``path`` facing along it (:func:`route_poses`), turning onto it from
    ``start_theta`` first, without touching a LETHAL cell? Cells the body already overlaps
    where it stands do not count (a robot pressed against a mark may leave it)."""
    poses = route_poses(path.points, footprint, costmap.info.resolution, start_theta)
    if poses.shape[0] == 0:
        return True
    return body.first_collision(footprint, costmap, poses, ignore_start=True) is None


class FootprintPlanner:
    """Plans routes a polygon body can drive (module docstring); a ``GlobalPlanner``."""

    def __init__(
        self,
        footprint: Footprint,
        config: GridPlannerConfig | None = None,
        lattice_config: LatticeConfig | None = None,
    ) -> None:
        self._footprint = footprint
        self._grid = GridPlanner(config)
        self._lattice = lattice_config or LatticeConfig()
        self._padded = [footprint.padded(p) for p in self._lattice.footprint_paddings]
        self.lattice_plans = 0
        """How many plans needed the lattice (for tests and benchmarks)."""

    @property
    def config(self) -> GridPlannerConfig:
        return self._grid.config

    def plan(
        self,
        costmap: CostGrid,
        start: Pose2D,
        goal: Pose2D,
        *,
        goal_tolerance: float | None = None,
    ) -> Path:
        """A route from ``start`` to ``goal`` the body can drive (see the module docstring).

        Raises:
            the grid planner's errors for start, goal and tolerance; :class:`NoPath` when no
            route lets the body through.
        """
        path = self._grid.plan(costmap, start, goal, goal_tolerance=goal_tolerance)
        end = (float(path.points[-1, 0]), float(path.points[-1, 1]))
        reached_goal = math.hypot(end[0] - goal.x, end[1] - goal.y) < 1e-9
        route = _Polyline.of(path.points)
        stretch: tuple[float, float] | None = None
        # With the most room to spare first; where nothing leaves any, the body as it is.
        for room in (*self._padded, self._footprint):
            if room is not self._footprint:
                stretch = _undrivable_stretch(path, self._footprint, room, costmap, start.theta,
                                              self._lattice.exact_near_start)
                if stretch is None:
                    return path
            if room is self._padded[0]:
                self.lattice_plans += 1
            assert stretch is not None
            found = self._round(costmap, path, route, stretch, start,
                                end if reached_goal else None, room)
            if found is not None:
                return found
        blocked = _first_touch(path, self._footprint, costmap, start.theta)
        if blocked is None:
            # The body fits the grid route facing along it, just not at the lattice's cells
            # and headings: the grid route it is.
            return path
        raise NoBodyRoute("no route the body fits: every way is narrower than the body at the "
                          "headings it can have there", route=path, blocked_at=blocked)

    def _round(
        self,
        costmap: CostGrid,
        path: Path,
        route: _Polyline,
        stretch: tuple[float, float],
        start: Pose2D,
        goal: tuple[float, float] | None,
        room: Footprint,
    ) -> Path | None:
        """A lattice route for ``room`` round the ``stretch`` [m] of the grid route ``path``
        the body cannot drive, or ``None``; the grid route itself when the way round is too
        large to search."""
        cfg = self._lattice
        if route.length > cfg.local_repair_over:
            # A long route: search round the stretch the body cannot drive, then splice.
            s0 = max(stretch[0] - cfg.repair_margin, 0.0)
            s1 = min(stretch[1] + cfg.repair_margin, route.length)
            if s1 < route.length:
                local, _ = self._search(costmap, route, s0, s1, start, None, room)
                if local is not None:
                    return _spliced(route, s0, s1, local, path.cost)
        whole, searched = self._search(costmap, route, 0.0, route.length, start, goal, room)
        if whole is None and not searched:
            # Too far round to search for the body: the grid route it is, and the controller
            # and the closed passages deal with the stretch.
            log.warning("route of %.0f m not drivable by the body and too large to search "
                        "round; keeping the grid route", route.length)
            return path
        return whole

    def reachable(self, costmap: CostGrid, start: Pose2D, goal: Pose2D) -> bool:
        try:
            self.plan(costmap, start, goal)
        except PlanningError:
            return False
        return True

    def _search(
        self,
        costmap: CostGrid,
        route: _Polyline,
        s0: float,
        s1: float,
        start: Pose2D,
        goal: tuple[float, float] | None,
        room: Footprint,
    ) -> tuple[Path | None, bool]:
        """The lattice route from the route's point at ``s0`` [m] (the robot's own pose at 0)
        to its point at ``s1``, in windows round that stretch (``None`` if none holds one), and
        whether any window was small enough to search."""
        info = costmap.info
        grid = np.ascontiguousarray(costmap.costs, dtype=np.uint8)
        cfg = self._grid.config
        unknown = cost_values.MAX_NON_OBSTACLE if cfg.allow_unknown else None
        # Inscribed cells are passable here at their (high) price: the body check is exact.
        mult = step_multipliers(cost_weight=cfg.cost_weight, lethal_threshold=cost_values.INSCRIBED,
                                unknown_cost=unknown, escape_below=cost_values.LETHAL)
        fp = self._footprint
        if s0 > 0.0:
            x, y = route.point_at(s0)
            start = Pose2D(x, y, route.heading_at(s0))
        end = route.point_at(s1) if goal is None else goal
        sx, sy = info.world_to_cell(start.x, start.y)
        gx, gy = info.world_to_cell(float(end[0]), float(end[1]))
        sk = lattice.nearest_heading(start.theta - info.origin.theta)
        verts = np.ascontiguousarray(fp.vertices, dtype=np.float64)
        rot_step = fp.rotation_step(info.resolution)
        turn_cost = self._lattice.turn_cost / info.resolution
        start_ignore = body.overlapped_cells(fp, costmap, start)
        stretch = route.points[(route.cumulative >= s0) & (route.cumulative <= s1)]
        stretch = np.vstack([[start.x, start.y], stretch, [end]])
        near = np.zeros(grid.shape, dtype=np.bool_)
        searched = False
        for margin in self._lattice.window_margins:
            x0, y0, x1, y1 = _window(info, stretch, margin)
            if (x1 - x0) * (y1 - y0) * lattice.HEADINGS > self._lattice.max_states:
                log.debug("lattice window of %d x %d cells too large", x1 - x0, y1 - y0)
                break
            searched = True
            _mark_near(near, grid, info.resolution, room.circumscribed_radius,
                       (x0, y0, x1, y1))
            h = lattice.cost_to_go(grid, mult, gx, gy, x0, y0, x1, y1)
            states, cost, expansions = lattice.search(
                grid, mult, near, info.resolution, verts, rot_step, turn_cost, h, x0, y0,
                sx, sy, sk, gx, gy, self._lattice.max_expansions, start_ignore,
                np.ascontiguousarray(room.vertices, dtype=np.float64), self._exact_within(info),
            )
            log.debug("lattice search in [%d, %d) x [%d, %d): %d states expanded, %s", x0, x1,
                      y0, y1, expansions, "found" if states.shape[0] else "none")
            if states.shape[0]:
                return self._route(info, grid, mult, near, verts, rot_step, states, cost, start,
                                   (float(end[0]), float(end[1])), room), True
            if (x0, y0, x1, y1) == (0, 0, info.width, info.height):
                break
        return None, searched

    def _exact_within(self, info: MapInfo) -> float:
        return self._lattice.exact_near_start / info.resolution

    def _route(
        self,
        info: MapInfo,
        grid: npt.NDArray[np.uint8],
        mult: npt.NDArray[np.float64],
        near: npt.NDArray[np.bool_],
        verts: npt.NDArray[np.float64],
        rot_step: float,
        states: npt.NDArray[np.int64],
        cost: float,
        start: Pose2D,
        goal: tuple[float, float] | None,
        room: Footprint,
    ) -> Path:
        span = max(int(self._lattice.max_leg / info.resolution), 1)
        kept = lattice.shorten(grid, mult, near, info.resolution, verts, rot_step, states,
                               start.theta - info.origin.theta, span,
                               np.ascontiguousarray(room.vertices, dtype=np.float64),
                               self._exact_within(info))
        points = info.cells_to_world(states[kept, :2])
        points[0] = (start.x, start.y)
        if goal is not None:
            points = np.vstack([points, [goal]]) if points.shape[0] < 2 else points
            points[-1] = goal
        if self._grid.config.point_spacing > 0.0:
            points = smoothing.densify(points, self._grid.config.point_spacing)
        return Path(points=points, cost=cost * info.resolution)


def _mark_near(
    near: npt.NDArray[np.bool_],
    grid: npt.NDArray[np.uint8],
    resolution: float,
    reach: float,
    window: tuple[int, int, int, int],
) -> None:
    """Mark in ``near`` the window's cells whose centre lies within ``reach`` (plus a cell) of a
    LETHAL cell: only there can some heading of the body touch one. The distance transform runs
    on the window grown by the reach, so obstacles just outside it count."""
    x0, y0, x1, y1 = window
    pad = int(math.ceil(reach / resolution)) + 2
    h, w = grid.shape
    gx0, gy0, gx1, gy1 = max(x0 - pad, 0), max(y0 - pad, 0), min(x1 + pad, w), min(y1 + pad, h)
    lethal = grid[gy0:gy1, gx0:gx1] == cost_values.LETHAL
    if not lethal.any():
        return
    distance = ndimage.distance_transform_edt(~lethal) * resolution
    near[y0:y1, x0:x1] = (distance <= reach + resolution)[y0 - gy0:y1 - gy0, x0 - gx0:x1 - gx0]


def _first_touch(
    path: Path, footprint: Footprint, costmap: CostGrid, start_theta: float
) -> Pose2D | None:
    """The first pose along ``path`` where the body itself touches a LETHAL cell it does not
    touch where it stands, or ``None``."""
    poses = route_poses(path.points, footprint, costmap.info.resolution, start_theta)
    if poses.shape[0] == 0:
        return None
    hit = body.first_collision(footprint, costmap, poses, ignore_start=True)
    return None if hit is None else Pose2D(*(float(v) for v in poses[hit]))


def _undrivable_stretch(
    path: Path,
    footprint: Footprint,
    padded: Footprint,
    costmap: CostGrid,
    start_theta: float,
    exact_near_start: float,
) -> tuple[float, float] | None:
    """Arc lengths [m] along ``path`` of the first and last pose the body cannot take
    (:func:`route_poses`), or ``None``. Within ``exact_near_start`` [m] of the start the body
    is checked as it is (what it touches where it stands aside), beyond with ``padded``."""
    poses = route_poses(path.points, footprint, costmap.info.resolution, start_theta)
    if poses.shape[0] == 0:
        return None
    far = np.hypot(poses[:, 0] - poses[0, 0], poses[:, 1] - poses[0, 1]) > exact_near_start
    hits = np.zeros(poses.shape[0], dtype=bool)
    hits[far] = body.collision_mask(padded, costmap, poses[far])
    first = body.first_collision(footprint, costmap, poses[~far], ignore_start=True)
    if first is not None:
        hits[np.flatnonzero(~far)[first]] = True
    if not hits.any():
        return None
    along = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(poses[:, :2], axis=0).T))])
    index = np.flatnonzero(hits)
    return float(along[index[0]]), float(along[index[-1]])


@dataclass(frozen=True, slots=True, eq=False)
class _Polyline:
    """A route's points without repeats and their arc lengths [m]."""

    points: npt.NDArray[np.float64]
    cumulative: npt.NDArray[np.float64]

    @classmethod
    def of(cls, points: npt.NDArray[np.float64]) -> _Polyline:
        pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        step = np.hypot(*np.diff(pts, axis=0).T)
        keep = np.concatenate([[True], step > 1e-12])
        return cls(pts[keep], np.concatenate([[0.0], np.cumsum(step[step > 1e-12])]))

    @property
    def length(self) -> float:
        return float(self.cumulative[-1])

    def point_at(self, s: float) -> tuple[float, float]:
        return (float(np.interp(s, self.cumulative, self.points[:, 0])),
                float(np.interp(s, self.cumulative, self.points[:, 1])))

    def heading_at(self, s: float) -> float:
        last = max(self.points.shape[0] - 2, 0)
        k = int(np.clip(np.searchsorted(self.cumulative, s, side="right") - 1, 0, last))
        d = self.points[min(k + 1, self.points.shape[0] - 1)] - self.points[k]
        return float(math.atan2(d[1], d[0]))


def _spliced(
    route: _Polyline, s0: float, s1: float, stretch: Path, cost: float
) -> Path:
    """The route up to ``s0``, ``stretch`` (from the point at ``s0`` to the point at ``s1``),
    and the route from ``s1`` on."""
    before = route.points[route.cumulative < s0 - 1e-9]
    after = route.points[route.cumulative > s1 + 1e-9]
    points = np.vstack([before, stretch.points, after])
    return Path(points=points, cost=cost + stretch.cost)


def _window(
    info: MapInfo, points: npt.NDArray[np.float64], margin: float
) -> tuple[int, int, int, int]:
    cells = info.world_to_cells(np.asarray(points, dtype=np.float64).reshape(-1, 2))
    pad = int(math.ceil(margin / info.resolution))
    x0 = max(int(cells[:, 0].min()) - pad, 0)
    y0 = max(int(cells[:, 1].min()) - pad, 0)
    x1 = min(int(cells[:, 0].max()) + pad + 1, info.width)
    y1 = min(int(cells[:, 1].max()) + pad + 1, info.height)
    return (x0, y0, x1, y1)
