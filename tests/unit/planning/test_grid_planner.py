from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.errors import ConfigError
from polynav.geometry import Pose2D
from polynav.maps import costs
from polynav.maps.ascii import map_from_ascii
from polynav.maps.costmap import Costmap, CostmapConfig
from polynav.maps.map import MapInfo
from polynav.planning.errors import GoalOccupied, NoPath, OutsideMap, StartOccupied
from polynav.planning.grid_planner import GridPlanner, GridPlannerConfig
from tests.unit.planning.grids import Grid, grid_from_ascii, random_costs, touched_cells

SQRT2 = math.sqrt(2.0)
INSCRIBED_STEP = 1.0 + 3.0 * 253 / 252
RAW = GridPlannerConfig(smooth=False, point_spacing=0.0)


def _cells_touched_by(grid: Grid, points: np.ndarray) -> set[tuple[int, int]]:
    """Every cell the polyline's segments touch (supercover), in cell coordinates."""
    info = grid.info
    c, s = math.cos(info.origin.theta), math.sin(info.origin.theta)
    local = []
    for x, y in points:
        dx, dy = x - info.origin.x, y - info.origin.y
        local.append(((c * dx + s * dy) / info.resolution, (-s * dx + c * dy) / info.resolution))
    out: set[tuple[int, int]] = set()
    for (ax, ay), (bx, by) in zip(local[:-1], local[1:], strict=True):
        out |= touched_cells(ax, ay, bx, by)
    return out


def test_plan_starts_and_ends_at_the_exact_positions_with_cost_in_metres() -> None:
    grid = grid_from_ascii(
        """
        .....
        .....
        .....
        """,
        resolution=0.5,
        origin=Pose2D(1.0, 2.0),
    )
    start, goal = Pose2D(1.3, 2.2), Pose2D(3.1, 3.4)
    path = GridPlanner(GridPlannerConfig(point_spacing=0.0)).plan(grid, start, goal)
    assert path.points.tolist() == [[1.3, 2.2], [3.1, 3.4]]
    assert path.cost == pytest.approx(0.5 * (2 + 2 * SQRT2), abs=1e-12)


def test_unsmoothed_plan_follows_cell_centres_between_the_exact_ends() -> None:
    grid = grid_from_ascii(
        """
        #####
        .....
        #####
        """
    )
    path = GridPlanner(RAW).plan(grid, Pose2D(0.2, 1.7), Pose2D(4.6, 1.4))
    assert path.points.tolist() == [[0.2, 1.7], [1.5, 1.5], [2.5, 1.5], [3.5, 1.5], [4.6, 1.4]]
    assert path.cost == 4.0


def test_plan_fails_with_outside_map_when_start_or_goal_is_off_the_grid() -> None:
    grid = grid_from_ascii("...\n...")
    planner = GridPlanner()
    with pytest.raises(OutsideMap, match="start"):
        planner.plan(grid, Pose2D(-0.1, 0.5), Pose2D(2.5, 0.5))
    with pytest.raises(OutsideMap, match="goal"):
        planner.plan(grid, Pose2D(0.5, 0.5), Pose2D(2.5, 2.0))


def test_plan_fails_with_start_occupied_when_start_in_wall() -> None:
    grid = grid_from_ascii("#..")
    with pytest.raises(StartOccupied):
        GridPlanner().plan(grid, Pose2D(0.5, 0.5), Pose2D(2.5, 0.5))


@pytest.mark.parametrize("cell", ["#", "I", "?"])
def test_plan_fails_with_goal_occupied_when_goal_cell_is_not_traversable(cell: str) -> None:
    grid = grid_from_ascii(f"...{cell}")
    with pytest.raises(GoalOccupied):
        GridPlanner().plan(grid, Pose2D(0.5, 0.5), Pose2D(3.5, 0.5))


def test_plan_fails_with_no_path_when_goal_is_walled_off() -> None:
    grid = grid_from_ascii(
        """
        ..#..
        ..#..
        """
    )
    with pytest.raises(NoPath):
        GridPlanner().plan(grid, Pose2D(0.5, 0.5), Pose2D(4.5, 1.5))


def test_goal_tolerance_ends_at_the_nearest_reachable_cell_when_goal_is_occupied() -> None:
    grid = grid_from_ascii(
        """
        .......
        .####..
        .......
        """
    )
    planner = GridPlanner(GridPlannerConfig(smooth=False, point_spacing=0.0, goal_tolerance=1.0))
    path = planner.plan(grid, Pose2D(0.5, 0.5), Pose2D(2.5, 1.3))
    # (2, 0) is 0.8 m from the goal; (2, 2) is 1.2 m away, beyond the tolerance.
    assert path.points.tolist() == [[0.5, 0.5], [1.5, 0.5], [2.5, 0.5]]
    assert path.cost == 2.0


def test_goal_tolerance_ends_near_a_free_goal_that_cannot_be_reached() -> None:
    grid = grid_from_ascii(
        """
        ......
        ..###.
        ..#.#.
        ..###.
        """
    )
    planner = GridPlanner(GridPlannerConfig(smooth=False, point_spacing=0.0, goal_tolerance=2.0))
    path = planner.plan(grid, Pose2D(0.5, 0.5), Pose2D(3.5, 1.5))
    # (1, 1), (5, 1) and (3, 3) are all 2 m away; the lowest row, then column, wins.
    assert path.points[-1].tolist() == [1.5, 1.5]
    assert path.cost == pytest.approx(SQRT2, abs=1e-12)
    tight = GridPlanner(GridPlannerConfig(goal_tolerance=0.5))
    with pytest.raises(NoPath):
        tight.plan(grid, Pose2D(0.5, 0.5), Pose2D(3.5, 1.5))


def test_goal_tolerance_with_nothing_free_nearby_is_still_goal_occupied() -> None:
    grid = grid_from_ascii(
        """
        ......
        ..III.
        ..I#I.
        ..III.
        """
    )
    with pytest.raises(GoalOccupied):
        GridPlanner(GridPlannerConfig(goal_tolerance=1.2)).plan(
            grid, Pose2D(0.5, 0.5), Pose2D(3.5, 1.5)
        )


def test_start_in_inscribed_cell_escapes_then_never_enters_inscribed_cells_again() -> None:
    grid = grid_from_ascii(
        """
        #########
        #II...I..
        #########
        """
    )
    # Without the escape rule, the inscribed (6, 1) would block; it still must: once out, the
    # path may not enter inscribed cells, so the goal beyond it is unreachable.
    with pytest.raises(NoPath):
        GridPlanner(RAW).plan(grid, Pose2D(1.5, 1.5), Pose2D(8.5, 1.5))
    path = GridPlanner(RAW).plan(grid, Pose2D(1.4, 1.6), Pose2D(5.5, 1.5))
    assert path.points[0].tolist() == [1.4, 1.6]
    assert path.points[-1].tolist() == [5.5, 1.5]
    assert path.cost == pytest.approx(INSCRIBED_STEP + 3.0, abs=1e-12)


def test_start_in_inscribed_cell_also_escapes_with_theta_star() -> None:
    grid = grid_from_ascii(
        """
        .......
        .......
        II.....
        II.....
        """
    )
    planner = GridPlanner(GridPlannerConfig(algorithm="theta_star", point_spacing=0.0))
    path = planner.plan(grid, Pose2D(0.5, 0.5), Pose2D(6.5, 3.5))
    assert path.points[0].tolist() == [0.5, 0.5]
    assert path.points[-1].tolist() == [6.5, 3.5]
    # Out of the 2x2 inscribed block first (one inscribed diagonal step), then any-angle.
    assert path.cost < INSCRIBED_STEP * SQRT2 + math.hypot(5, 2) + 1.0
    touched = _cells_touched_by(grid, path.points[2:])
    assert all(grid.costs[iy, ix] < costs.INSCRIBED for ix, iy in touched)


def test_unknown_cells_are_impassable_unless_allowed_and_then_priced_dear() -> None:
    grid = grid_from_ascii(
        """
        #####
        .???.
        #####
        """
    )
    with pytest.raises(NoPath):
        GridPlanner(RAW).plan(grid, Pose2D(0.5, 1.5), Pose2D(4.5, 1.5))
    config = GridPlannerConfig(smooth=False, point_spacing=0.0, allow_unknown=True)
    path = GridPlanner(config).plan(grid, Pose2D(0.5, 1.5), Pose2D(4.5, 1.5))
    assert path.cost == pytest.approx(3 * (1 + 3.0 * 252 / 252) + 1.0, abs=1e-12)


def test_cost_weight_trades_length_for_distance_from_costly_cells() -> None:
    grid = grid_from_ascii(
        """
        .....
        .###.
        .999.
        """
    )
    start, goal = Pose2D(0.5, 0.5), Pose2D(4.5, 0.5)
    heavy = GridPlanner(RAW).plan(grid, start, goal)
    assert heavy.cost == 8.0
    assert [1.5, 0.5] not in heavy.points.tolist()
    light = GridPlanner(GridPlannerConfig(smooth=False, point_spacing=0.0, cost_weight=1.0))
    assert light.plan(grid, start, goal).cost == 7.0


def test_start_and_goal_in_one_cell_give_a_two_point_path_of_cost_zero() -> None:
    grid = grid_from_ascii("...")
    path = GridPlanner().plan(grid, Pose2D(1.2, 0.3), Pose2D(1.8, 0.6))
    assert path.points.tolist()[0] == [1.2, 0.3] and path.points.tolist()[-1] == [1.8, 0.6]
    assert path.cost == 0.0
    same = GridPlanner().plan(grid, Pose2D(1.5, 0.5), Pose2D(1.5, 0.5))
    assert same.points.tolist() == [[1.5, 0.5], [1.5, 0.5]]


def test_points_are_densified_to_the_configured_spacing() -> None:
    grid = grid_from_ascii("." * 40 + "\n" + "." * 40, resolution=0.05)
    path = GridPlanner().plan(grid, Pose2D(0.01, 0.01), Pose2D(1.99, 0.09))
    steps = np.hypot(*np.diff(path.points, axis=0).T)
    assert steps.max() <= 0.05 + 1e-12
    assert path.points[0].tolist() == [0.01, 0.01] and path.points[-1].tolist() == [1.99, 0.09]
    assert path.length == pytest.approx(math.hypot(1.98, 0.08), abs=1e-12)


@pytest.mark.parametrize("algorithm", ["astar", "theta_star"])
def test_smoothed_paths_never_touch_inscribed_or_lethal_cells(algorithm: str) -> None:
    rng = np.random.default_rng(31)
    planner = GridPlanner(GridPlannerConfig(algorithm=algorithm, point_spacing=0.0))
    planned = 0
    for _ in range(25):
        values = random_costs(rng, 30, 30, blocked=0.05, costly=0.4)
        lethal = values == costs.LETHAL
        near = np.zeros_like(lethal)
        near[1:, :] |= lethal[:-1, :]
        near[:-1, :] |= lethal[1:, :]
        near[:, 1:] |= lethal[:, :-1]
        near[:, :-1] |= lethal[:, 1:]
        values[near & ~lethal] = costs.INSCRIBED
        values[0, 0] = values[29, 29] = 0
        grid = Grid(MapInfo(resolution=1.0, width=30, height=30), values)
        try:
            path = planner.plan(grid, Pose2D(0.3, 0.6), Pose2D(29.7, 29.2))
        except NoPath:
            continue
        planned += 1
        for ix, iy in _cells_touched_by(grid, path.points):
            assert values[iy, ix] < costs.INSCRIBED, (ix, iy)
    assert planned >= 10


def test_theta_star_paths_are_no_dearer_than_a_star_paths() -> None:
    rng = np.random.default_rng(8)
    astar = GridPlanner(GridPlannerConfig(point_spacing=0.0, cost_weight=0.0))
    theta = GridPlanner(GridPlannerConfig(algorithm="theta_star", point_spacing=0.0,
                                          cost_weight=0.0))
    for _ in range(15):
        values = np.where(rng.random((25, 25)) < 0.2, costs.LETHAL, 0).astype(np.uint8)
        values[0, 0] = values[24, 24] = 0
        grid = Grid(MapInfo(resolution=1.0, width=25, height=25), values)
        try:
            a = astar.plan(grid, Pose2D(0.5, 0.5), Pose2D(24.5, 24.5))
        except NoPath:
            continue
        t = theta.plan(grid, Pose2D(0.5, 0.5), Pose2D(24.5, 24.5))
        assert t.cost <= a.cost + 1e-9
        assert t.length <= a.length + 1e-9


def test_plan_on_a_rotated_map_keeps_exact_ends_and_clear_segments() -> None:
    grid = grid_from_ascii(
        """
        ......
        .##...
        ......
        """,
        resolution=0.5,
        origin=Pose2D(2.0, -1.0, math.pi / 2),
    )
    start = Pose2D(*grid.info.cell_to_world(0.2, 0.1))
    goal = Pose2D(*grid.info.cell_to_world(5.1, 2.3))
    path = GridPlanner(GridPlannerConfig(point_spacing=0.0)).plan(grid, start, goal)
    assert path.points[0] == pytest.approx([start.x, start.y], abs=1e-12)
    assert path.points[-1] == pytest.approx([goal.x, goal.y], abs=1e-12)
    for ix, iy in _cells_touched_by(grid, path.points):
        assert grid.costs[iy, ix] < costs.INSCRIBED


def test_plans_on_a_layered_costmap() -> None:
    grid = map_from_ascii(
        """
        ####################
        #..................#
        #..................#
        #..................#
        #........#.........#
        #........#.........#
        #........#.........#
        #..................#
        #..................#
        #..................#
        ####################
        """,
        resolution=0.1,
    )
    costmap = Costmap.from_map(grid, CostmapConfig(robot_radius=0.15, inflation_radius=0.4))
    path = GridPlanner().plan(costmap, Pose2D(0.35, 0.45), Pose2D(1.65, 0.45))
    assert path.points[0].tolist() == [0.35, 0.45] and path.points[-1].tolist() == [1.65, 0.45]
    local = Grid(costmap.info, np.asarray(costmap.costs))
    for ix, iy in _cells_touched_by(local, path.points):
        assert costmap.costs[iy, ix] < costs.INSCRIBED
    # Around one end of the wall (through the 0.1 m gap of free cells), not through it.
    assert path.length > 1.4


def test_reachable_answers_without_raising() -> None:
    grid = grid_from_ascii(
        """
        ..#..
        ..#..
        """
    )
    planner = GridPlanner()
    assert planner.reachable(grid, Pose2D(0.5, 0.5), Pose2D(1.5, 1.5))
    assert not planner.reachable(grid, Pose2D(0.5, 0.5), Pose2D(4.5, 1.5))
    assert not planner.reachable(grid, Pose2D(0.5, 0.5), Pose2D(2.5, 0.5))
    assert not planner.reachable(grid, Pose2D(0.5, 0.5), Pose2D(9.5, 0.5))


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("algorithm", "dijkstra"),
        ("cost_weight", -1.0),
        ("cost_weight", math.inf),
        ("goal_tolerance", -0.1),
        ("point_spacing", -0.05),
        ("shortcut_cost_ratio", 0.5),
    ],
)
def test_config_rejects_out_of_range_values_naming_the_key(field: str, value: object) -> None:
    with pytest.raises(ConfigError) as error:
        GridPlannerConfig(**{field: value})  # type: ignore[arg-type]
    assert error.value.key == f"planner.{field}"
