"""The grid planner: world poses in, a smoothed world path out, typed errors when it cannot.

This is the wrapper around the search kernels (as Nav2's ``theta_star_planner.cpp`` wraps
``theta_star.cpp``, STYLE R2). It converts the start and goal to cells, checks them, runs the
search named by the configuration (``astar`` or ``theta_star``) on the costmap, and turns the
cells back into world points, with the robot's exact start position first and the exact goal
position last.

The rules, in the order they apply:

* a start or goal outside the map raises :class:`OutsideMap`; a LETHAL start raises
  :class:`StartOccupied`;
* cells at or above INSCRIBED are impassable (UNKNOWN too, unless ``allow_unknown``, in which case
  they are priced as the dearest non-obstacle cost so that known floor is preferred);
* an INSCRIBED start (the robot pressed near a wall, not in it) is left through inscribed,
  non-lethal cells, and the path never enters inscribed cells again once out (``astar``);
* a goal cell that is LETHAL, INSCRIBED or otherwise impassable raises :class:`GoalOccupied`,
  unless ``goal_tolerance`` is positive: then, as for a goal that is free but unreachable, the
  plan ends at the reachable cell closest to the goal within the tolerance (:class:`NoPath` if
  there is none, :class:`GoalOccupied` if no cell within it is even passable);
* ``Path.cost`` is the search's cost in metres: length plus the cost-weight penalty. Smoothing
  (``smoothing.shortcut``) never raises it, and the points are then spaced ``point_spacing``
  apart at most for the controller (``smoothing.densify``).

A planner keeps search buffers for the last map size, so keep one per costmap user; it is not
thread-safe.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from polynav.errors import ConfigError
from polynav.geometry import Pose2D
from polynav.maps import costs as cost_values
from polynav.maps.interface import CostGrid
from polynav.maps.map import MapInfo
from polynav.planning import smoothing
from polynav.planning.astar import AStar
from polynav.planning.errors import GoalOccupied, NoPath, OutsideMap, StartOccupied
from polynav.planning.grid_search import CellPath, GridSearch, step_multipliers
from polynav.planning.line_of_sight import segment_cost
from polynav.planning.path import Path
from polynav.planning.theta_star import ThetaStar

log = logging.getLogger(__name__)

SEARCHES: dict[str, Callable[[], GridSearch]] = {"astar": AStar, "theta_star": ThetaStar}
"""Search algorithms by configuration name."""

MAX_COST_WEIGHT = 100.0
_SQRT2 = math.sqrt(2.0)


@dataclass(frozen=True, slots=True)
class GridPlannerConfig:
    """How the grid planner searches and post-processes (SI units).

    Attributes:
        algorithm: search name in :data:`SEARCHES`: ``astar`` (8-connected, optimal) or
            ``theta_star`` (any-angle).
        cost_weight: how strongly costs repel the path: entering a cell of cost 252 makes a
            step ``1 + cost_weight`` times as dear (0 plans shortest paths, ignoring inflation).
        allow_unknown: plan through UNKNOWN cells (at the dearest non-obstacle price).
        goal_tolerance: radius [m] around an occupied or unreachable goal within which the
            nearest reachable cell is accepted instead; 0 means the goal itself or an error.
        smooth: shortcut the grid path by line of sight (``smoothing.shortcut``).
        point_spacing: largest distance [m] between consecutive path points; 0 keeps only the
            path's vertices.
        shortcut_cost_ratio: how much dearer than the path part it replaces a shortcut may be.
    """

    algorithm: str = "astar"
    cost_weight: float = 3.0
    allow_unknown: bool = False
    goal_tolerance: float = 0.0
    smooth: bool = True
    point_spacing: float = 0.05
    shortcut_cost_ratio: float = 1.0

    def __post_init__(self) -> None:
        _check(
            self.algorithm in SEARCHES,
            "algorithm",
            f"{self.algorithm!r} is not one of {', '.join(sorted(SEARCHES))}",
        )
        _check(
            math.isfinite(self.cost_weight) and 0.0 <= self.cost_weight <= MAX_COST_WEIGHT,
            "cost_weight",
            f"must be within 0..{MAX_COST_WEIGHT:g}",
        )
        _check(
            math.isfinite(self.goal_tolerance) and self.goal_tolerance >= 0.0,
            "goal_tolerance",
            "must be a finite value >= 0",
        )
        _check(
            math.isfinite(self.point_spacing) and self.point_spacing >= 0.0,
            "point_spacing",
            "must be a finite value >= 0",
        )
        _check(
            math.isfinite(self.shortcut_cost_ratio) and self.shortcut_cost_ratio >= 1.0,
            "shortcut_cost_ratio",
            "must be a finite value >= 1",
        )


def _check(ok: bool, field: str, reason: str) -> None:
    if not ok:
        raise ConfigError(f"planner.{field}", reason)


@dataclass(frozen=True, slots=True, eq=False)
class _Tables:
    """The step multipliers of one query: the search's, and the escape variant if needed."""

    search: npt.NDArray[np.float64]
    escape: npt.NDArray[np.float64] | None


class GridPlanner:
    """Plans on a cost grid with the configured search (module docstring for the rules)."""

    def __init__(self, config: GridPlannerConfig | None = None) -> None:
        self._config = config or GridPlannerConfig()
        self._search = SEARCHES[self._config.algorithm]()
        # Theta* cannot leave a start it may not stand on; A* takes that first leg.
        self._astar = self._search if self._config.algorithm == "astar" else AStar()
        self._last: GridSearch = self._search

    @property
    def config(self) -> GridPlannerConfig:
        return self._config

    def plan(
        self,
        costmap: CostGrid,
        start: Pose2D,
        goal: Pose2D,
        *,
        goal_tolerance: float | None = None,
    ) -> Path:
        """A path from ``start`` to ``goal`` over ``costmap``.

        Args:
            costmap: the cost grid (a live costmap or a snapshot); read, never written.
            start: the robot's pose; only the position matters.
            goal: the goal pose; only the position matters.
            goal_tolerance: this plan's ``goal_tolerance`` [m] (``None``: the configured one).

        Returns:
            At least two world points [m], the exact start first and the exact goal last (or
            the centre of the substitute cell under ``goal_tolerance``), with ``cost`` in metres.

        Raises:
            OutsideMap: start or goal outside the grid.
            StartOccupied: the start cell is LETHAL.
            GoalOccupied: the goal cell is impassable and no tolerance applies.
            NoPath: nothing reachable at (or, with a tolerance, near) the goal.
        """
        info = costmap.info
        grid = np.ascontiguousarray(costmap.costs, dtype=np.uint8)
        start_cell = _cell(info, start, "start")
        goal_cell = _cell(info, goal, "goal")
        tables = self._tables(int(grid[start_cell[1], start_cell[0]]), start_cell)
        tolerance = self._config.goal_tolerance if goal_tolerance is None else goal_tolerance
        found, reached_goal = self._find(
            grid, info, start_cell, goal_cell, goal, tables, tolerance
        )
        cells = found.cells
        if self._config.smooth:
            measure = tables.search if tables.escape is None else tables.escape
            cells = smoothing.shortcut(
                grid,
                cells,
                check_multipliers=tables.search,
                measure_multipliers=measure,
                max_cost_ratio=self._config.shortcut_cost_ratio,
            )
        end = (goal.x, goal.y) if reached_goal else None
        points = _world_points(info, grid, tables.search, cells, (start.x, start.y), end)
        if self._config.point_spacing > 0.0:
            points = smoothing.densify(points, self._config.point_spacing)
        cost = found.cost * info.resolution
        log.debug(
            "planned %d cells (%d points, %d expansions), cost %.3f m",
            found.cells.shape[0],
            points.shape[0],
            found.expansions,
            cost,
        )
        return Path(points=points, cost=cost)

    def reachable(self, costmap: CostGrid, start: Pose2D, goal: Pose2D) -> bool:
        """True if :meth:`plan` would succeed (same rules, without building the path)."""
        info = costmap.info
        grid = np.ascontiguousarray(costmap.costs, dtype=np.uint8)
        try:
            start_cell = _cell(info, start, "start")
            goal_cell = _cell(info, goal, "goal")
            tables = self._tables(int(grid[start_cell[1], start_cell[0]]), start_cell)
            self._find(grid, info, start_cell, goal_cell, goal, tables, self._config.goal_tolerance)
        except (OutsideMap, StartOccupied, GoalOccupied, NoPath):
            return False
        return True

    def _tables(self, start_cost: int, start_cell: tuple[int, int]) -> _Tables:
        cfg = self._config
        unknown = cost_values.MAX_NON_OBSTACLE if cfg.allow_unknown else None
        search = step_multipliers(
            cost_weight=cfg.cost_weight,
            lethal_threshold=cost_values.INSCRIBED,
            unknown_cost=unknown,
        )
        if start_cost == cost_values.LETHAL:
            raise StartOccupied(f"start cell {start_cell} is lethal")
        escape = None
        if start_cost == cost_values.INSCRIBED:
            escape = step_multipliers(
                cost_weight=cfg.cost_weight,
                lethal_threshold=cost_values.INSCRIBED,
                unknown_cost=unknown,
                escape_below=cost_values.LETHAL,
            )
        return _Tables(search=search, escape=escape)

    def _find(
        self,
        grid: npt.NDArray[np.uint8],
        info: MapInfo,
        start: tuple[int, int],
        goal: tuple[int, int],
        goal_pose: Pose2D,
        tables: _Tables,
        tolerance: float,
    ) -> tuple[CellPath, bool]:
        """The cell path to the goal, or under the tolerance to a substitute; and whether the
        path ends at the goal cell itself."""
        goal_free = bool(np.isfinite(tables.search[grid[goal[1], goal[0]]]))
        if not goal_free and tolerance <= 0.0:
            raise GoalOccupied(f"goal cell {goal} is occupied (cost {grid[goal[1], goal[0]]})")
        if goal_free:
            found = self._search_leg(grid, start, goal, tables)
            if found is not None:
                return found, True
            if tolerance <= 0.0:
                raise NoPath(f"no path from {start} to {goal}")
        candidates = _candidates(info, grid, tables.search, goal_pose, tolerance)
        if candidates.shape[0] == 0:
            raise GoalOccupied(f"goal cell {goal} is occupied and no cell within "
                               f"{tolerance:g} m of it is free")
        if not goal_free:
            # Nothing searched yet: try the closest candidate, which usually works.
            first = (int(candidates[0, 0]), int(candidates[0, 1]))
            found = self._search_leg(grid, start, first, tables)
            if found is not None:
                return found, False
        # The failed search closed exactly the cells reachable from the start.
        reachable = candidates[self._last.closed(candidates)]
        if reachable.shape[0] == 0:
            raise NoPath(f"no path from {start} to within {tolerance:g} m of {goal}")
        target = (int(reachable[0, 0]), int(reachable[0, 1]))
        found = self._search_leg(grid, start, target, tables)
        if found is None:  # pragma: no cover - the closed set says it is reachable
            raise NoPath(f"no path from {start} to {target}")
        log.debug("goal %s unreachable; planning to %s within tolerance", goal, target)
        return found, False

    def _search_leg(
        self,
        grid: npt.NDArray[np.uint8],
        start: tuple[int, int],
        goal: tuple[int, int],
        tables: _Tables,
    ) -> CellPath | None:
        """One search from ``start`` to ``goal``; records which search ran for ``closed``."""
        start_free = bool(np.isfinite(tables.search[grid[start[1], start[0]]]))
        if start_free or self._search is self._astar:
            self._last = self._search
            return self._search.search(
                grid, start, goal, multipliers=tables.search, escape_multipliers=tables.escape
            )
        # Theta* from a start it may not stand on: A* leaves the start, Theta* does the rest.
        self._last = self._astar
        lead = self._astar.search(
            grid, start, goal, multipliers=tables.search, escape_multipliers=tables.escape
        )
        if lead is None:
            return None
        free = np.isfinite(tables.search[grid[lead.cells[:, 1], lead.cells[:, 0]]])
        exit_index = int(np.argmax(free))
        exit_cell = (int(lead.cells[exit_index, 0]), int(lead.cells[exit_index, 1]))
        rest = self._search.search(grid, exit_cell, goal, multipliers=tables.search)
        if rest is None:  # pragma: no cover - A* just reached the goal from there
            return None
        escape = tables.escape if tables.escape is not None else tables.search
        lead_cost = _step_cost(grid, escape, lead.cells[: exit_index + 1])
        cells = np.vstack([lead.cells[:exit_index], rest.cells])
        return CellPath(cells=cells, cost=lead_cost + rest.cost,
                        expansions=lead.expansions + rest.expansions)


def _cell(info: MapInfo, pose: Pose2D, what: str) -> tuple[int, int]:
    ix, iy = info.world_to_cell(pose.x, pose.y)
    if not info.contains(ix, iy):
        raise OutsideMap(f"{what} ({pose.x:.3f}, {pose.y:.3f}) is outside the map")
    return (ix, iy)


def _step_cost(
    grid: npt.NDArray[np.uint8],
    table: npt.NDArray[np.float64],
    cells: npt.NDArray[np.int64],
) -> float:
    """A*'s cost of a cell chain: each step's length times the multiplier of the cell entered
    (summed in the same order as the search, so it reproduces the search's figure)."""
    total = 0.0
    for k in range(1, cells.shape[0]):
        diagonal = cells[k, 0] != cells[k - 1, 0] and cells[k, 1] != cells[k - 1, 1]
        step = _SQRT2 if diagonal else 1.0
        total += step * float(table[grid[cells[k, 1], cells[k, 0]]])
    return total


def _candidates(
    info: MapInfo,
    grid: npt.NDArray[np.uint8],
    table: npt.NDArray[np.float64],
    goal: Pose2D,
    tolerance: float,
) -> npt.NDArray[np.int64]:
    """Passable cells whose centres lie within ``tolerance`` of the goal, nearest first."""
    gx, gy = info.world_to_cell(goal.x, goal.y)
    reach = int(math.ceil(tolerance / info.resolution)) + 1
    x0, x1 = max(0, gx - reach), min(info.width, gx + reach + 1)
    y0, y1 = max(0, gy - reach), min(info.height, gy + reach + 1)
    iy, ix = np.mgrid[y0:y1, x0:x1]
    cells = np.column_stack([ix.ravel(), iy.ravel()]).astype(np.int64)
    centres = info.cells_to_world(cells)
    distance = np.hypot(centres[:, 0] - goal.x, centres[:, 1] - goal.y)
    passable = np.isfinite(table[grid[cells[:, 1], cells[:, 0]]])
    inside = (distance <= tolerance) & passable
    order = np.lexsort((cells[inside, 0], cells[inside, 1], distance[inside]))
    return np.asarray(cells[inside][order])


def _grid_coords(info: MapInfo, x: float, y: float) -> tuple[float, float]:
    """World point to continuous cell coordinates (``MapInfo.world_to_cell`` before flooring;
    line of sight from an exact position needs the fraction)."""
    c, s = math.cos(info.origin.theta), math.sin(info.origin.theta)
    dx, dy = x - info.origin.x, y - info.origin.y
    return ((c * dx + s * dy) / info.resolution, (-s * dx + c * dy) / info.resolution)


def _world_points(
    info: MapInfo,
    grid: npt.NDArray[np.uint8],
    table: npt.NDArray[np.float64],
    cells: npt.NDArray[np.int64],
    start: tuple[float, float],
    goal: tuple[float, float] | None,
) -> npt.NDArray[np.float64]:
    """Cell centres as world points, with the exact start (and goal, if given) at the ends.

    An exact end replaces its cell's centre when the segment from it to the next point is clear
    under the search table; otherwise the path keeps the centre, and the end joins it with a hop
    inside its own cell.
    """
    centres = list(info.cells_to_world(cells))
    count = len(centres)
    points = [np.asarray(start, dtype=np.float64), *centres]
    if goal is not None:
        points.append(np.asarray(goal, dtype=np.float64))
    dropped: set[int] = set()
    if len(points) > 2 and _clear(info, grid, table, points[0], points[2]):
        dropped.add(1)
    if goal is not None and count not in dropped:
        before = count - 1 if count - 1 not in dropped else count - 2
        if _clear(info, grid, table, points[before], points[-1]):
            dropped.add(count)
    kept = np.array([p for k, p in enumerate(points) if k not in dropped], dtype=np.float64)
    # An exact end on its cell's centre would repeat a point; a start on the goal still gives
    # two points, so a controller always gets a segment.
    distinct = np.ones(kept.shape[0], dtype=bool)
    distinct[1:] = np.any(np.diff(kept, axis=0) != 0.0, axis=1)
    if distinct.sum() < 2:
        return np.asarray(kept[[0, -1]])
    return np.asarray(kept[distinct])


def _clear(
    info: MapInfo,
    grid: npt.NDArray[np.uint8],
    table: npt.NDArray[np.float64],
    a: tuple[float, float] | npt.NDArray[np.float64],
    b: tuple[float, float] | npt.NDArray[np.float64],
) -> bool:
    ax, ay = _grid_coords(info, float(a[0]), float(a[1]))
    bx, by = _grid_coords(info, float(b[0]), float(b[1]))
    return bool(np.isfinite(segment_cost(grid, table, ax, ay, bx, by)))
