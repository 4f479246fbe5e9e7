from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from polynav.maps import costs
from polynav.maps.movingai import load_grid, load_scenarios
from polynav.planning.astar import AStar
from polynav.planning.grid_search import step_multipliers
from tests.unit.planning.grids import costs_from_ascii, dijkstra_costs, random_costs

SQRT2 = math.sqrt(2.0)
PLAIN = step_multipliers(cost_weight=0.0)
WEIGHTED = step_multipliers(cost_weight=3.0)


def _cost(values: np.ndarray, start: tuple[int, int], goal: tuple[int, int], table=PLAIN) -> float:
    found = AStar().search(values, start, goal, multipliers=table)
    assert found is not None
    return found.cost


def _assert_valid_path(values: np.ndarray, cells: np.ndarray, table: np.ndarray) -> None:
    """Every step is a legal 8-connected move under the no-corner-cutting rule."""
    a, b = cells[:-1], cells[1:]
    step = b - a
    assert (np.abs(step).max(axis=1) == 1).all()
    passable = np.isfinite(table[values])
    assert passable[b[:, 1], b[:, 0]].all()
    diagonal = (step[:, 0] != 0) & (step[:, 1] != 0)
    assert passable[a[diagonal, 1], b[diagonal, 0]].all()
    assert passable[b[diagonal, 1], a[diagonal, 0]].all()


def test_straight_corridor_costs_its_length() -> None:
    values = costs_from_ascii(
        """
        #####
        .....
        #####
        """
    )
    found = AStar().search(values, (0, 1), (4, 1), multipliers=PLAIN)
    assert found is not None
    assert found.cost == 4.0
    assert found.cells.tolist() == [[0, 1], [1, 1], [2, 1], [3, 1], [4, 1]]


def test_open_ground_cost_is_the_octile_distance() -> None:
    values = np.zeros((20, 30), dtype=np.uint8)
    assert _cost(values, (2, 3), (27, 10)) == pytest.approx(18 + 7 * SQRT2, abs=1e-12)


def test_diagonal_between_two_blocked_corner_cells_is_not_a_path() -> None:
    values = costs_from_ascii(
        """
        .#
        #.
        """
    )
    assert AStar().search(values, (1, 0), (0, 1), multipliers=PLAIN) is None


def test_diagonal_with_one_blocked_side_cell_goes_around() -> None:
    values = costs_from_ascii(
        """
        ...
        .#.
        ...
        """
    )
    found = AStar().search(values, (1, 0), (2, 1), multipliers=PLAIN)
    assert found is not None
    assert found.cost == 2.0
    assert found.cells.tolist() == [[1, 0], [2, 0], [2, 1]]


def test_costly_cells_are_avoided_when_the_detour_is_cheaper() -> None:
    values = costs_from_ascii(
        """
        .....
        .###.
        .999.
        """
    )
    # Straight through three cells of cost 252: 3 * (1 + w) + 1; around the wall: 8 steps.
    assert _cost(values, (0, 0), (4, 0), step_multipliers(cost_weight=3.0)) == 8.0
    assert _cost(values, (0, 0), (4, 0), step_multipliers(cost_weight=1.0)) == 7.0
    assert _cost(values, (0, 0), (4, 0), PLAIN) == 4.0


def test_entering_a_cell_costs_step_times_one_plus_weighted_cost() -> None:
    values = costs_from_ascii(
        """
        ###
        .5.
        """
    )
    # One step into the cost-140 cell, one step out into a free cell.
    expected = (1.0 + 2.0 * 140 / 252) + 1.0
    assert _cost(values, (0, 0), (2, 0), step_multipliers(cost_weight=2.0)) == pytest.approx(
        expected, abs=1e-12
    )


def test_unreachable_goal_returns_none_and_closes_the_start_component() -> None:
    values = costs_from_ascii(
        """
        ..#..
        ..#..
        ..#..
        """
    )
    planner = AStar()
    assert planner.search(values, (0, 0), (4, 2), multipliers=PLAIN) is None
    left = np.array([[x, y] for x in range(2) for y in range(3)])
    right = np.array([[x, y] for x in range(3, 5) for y in range(3)])
    assert planner.closed(left).all()
    assert not planner.closed(right).any()


def test_goal_in_an_impassable_cell_is_never_reached() -> None:
    values = costs_from_ascii("..I")
    assert AStar().search(values, (0, 0), (2, 0), multipliers=WEIGHTED) is None


def test_start_equal_to_goal_is_a_one_cell_path_of_cost_zero() -> None:
    values = np.zeros((3, 3), dtype=np.uint8)
    found = AStar().search(values, (1, 1), (1, 1), multipliers=PLAIN)
    assert found is not None
    assert found.cost == 0.0
    assert found.cells.tolist() == [[1, 1]]


def test_start_cell_is_expanded_whatever_its_cost() -> None:
    values = costs_from_ascii("?..")
    found = AStar().search(values, (0, 0), (2, 0), multipliers=PLAIN)
    assert found is not None and found.cost == 2.0


def test_escape_table_leaves_inscribed_start_through_inscribed_cells() -> None:
    values = costs_from_ascii(
        """
        ######
        IIII..
        ######
        """
    )
    escape = step_multipliers(cost_weight=3.0, escape_below=costs.LETHAL)
    found = AStar().search(
        values, (0, 1), (5, 1), multipliers=WEIGHTED, escape_multipliers=escape
    )
    assert found is not None
    inscribed = 1.0 + 3.0 * 253 / 252
    assert found.cost == pytest.approx(3 * inscribed + 2.0, abs=1e-12)
    assert AStar().search(values, (0, 1), (5, 1), multipliers=WEIGHTED) is None


def test_escaped_path_never_re_enters_inscribed_cells() -> None:
    values = costs_from_ascii(
        """
        ...I...
        ...I...
        I..I...
        """
    )
    escape = step_multipliers(cost_weight=3.0, escape_below=costs.LETHAL)
    planner = AStar()
    # Crossing the inscribed column would be cheap, but it is not part of the start's region.
    assert planner.search(
        values, (0, 0), (6, 0), multipliers=WEIGHTED, escape_multipliers=escape
    ) is None
    found = planner.search(values, (0, 0), (2, 2), multipliers=WEIGHTED, escape_multipliers=escape)
    assert found is not None
    assert found.cost == pytest.approx(2 * SQRT2, abs=1e-12)


def test_escape_takes_the_cheapest_way_out_not_only_the_nearest_exit() -> None:
    values = costs_from_ascii(
        """
        #######
        #.IIII.
        ####I##
        ####..#
        """
    )
    escape = step_multipliers(cost_weight=3.0, escape_below=costs.LETHAL)
    # From (2, 2), the nearest free cell (1, 2) leads nowhere; the goal needs the other exits.
    found = AStar().search(values, (2, 2), (6, 2), multipliers=WEIGHTED, escape_multipliers=escape)
    assert found is not None
    assert found.cells[-1].tolist() == [6, 2]
    inscribed = 1.0 + 3.0 * 253 / 252
    assert found.cost == pytest.approx(3 * inscribed + 1.0, abs=1e-12)


def test_read_only_cost_arrays_are_accepted() -> None:
    values = np.zeros((4, 4), dtype=np.uint8)
    values.flags.writeable = False
    assert _cost(values, (0, 0), (3, 3)) == pytest.approx(3 * SQRT2, abs=1e-12)


def test_start_or_goal_outside_the_grid_is_a_value_error() -> None:
    values = np.zeros((4, 4), dtype=np.uint8)
    with pytest.raises(ValueError):
        AStar().search(values, (4, 0), (0, 0), multipliers=PLAIN)
    with pytest.raises(ValueError):
        AStar().search(values, (0, 0), (0, -1), multipliers=PLAIN)


def test_costs_match_an_independent_dijkstra_on_random_weighted_grids() -> None:
    rng = np.random.default_rng(7)
    planner = AStar()
    for trial in range(6):
        values = random_costs(rng, 24, 31, blocked=0.22, costly=0.5)
        table = step_multipliers(cost_weight=float(trial))
        free = np.argwhere(np.isfinite(table[values]))
        start_iy, start_ix = free[rng.integers(len(free))]
        start = (int(start_ix), int(start_iy))
        reference = dijkstra_costs(values, table, start)
        for goal_iy, goal_ix in free[rng.choice(len(free), size=25, replace=False)]:
            found = planner.search(values, start, (int(goal_ix), int(goal_iy)), multipliers=table)
            expected = reference[goal_iy, goal_ix]
            if not np.isfinite(expected):
                assert found is None
                continue
            assert found is not None
            assert found.cost == pytest.approx(expected, abs=1e-9)
            _assert_valid_path(values, found.cells, table)


def test_a_small_open_list_is_compacted_and_grown_without_changing_results() -> None:
    rng = np.random.default_rng(3)
    values = random_costs(rng, 60, 60, blocked=0.15, costly=0.6)
    values[0, 0] = values[59, 59] = values[0, 59] = 0
    small = AStar(capacity=4)
    default = AStar()
    for goal in [(59, 59), (59, 0), (30, 30)]:
        if values[goal[1], goal[0]] >= costs.INSCRIBED:
            continue
        a = small.search(values, (0, 0), goal, multipliers=WEIGHTED)
        b = default.search(values, (0, 0), goal, multipliers=WEIGHTED)
        assert (a is None) == (b is None)
        if a is not None and b is not None:
            assert a.cost == b.cost
            assert np.array_equal(a.cells, b.cells)


def test_buffers_are_reused_across_queries_and_grid_sizes() -> None:
    planner = AStar()
    big = np.zeros((50, 50), dtype=np.uint8)
    small = costs_from_ascii(
        """
        ...
        ##.
        ...
        """
    )
    for _ in range(3):
        assert planner.search(big, (0, 0), (49, 49), multipliers=PLAIN).cost == pytest.approx(
            49 * SQRT2, abs=1e-9
        )
        assert planner.search(small, (0, 0), (0, 2), multipliers=PLAIN).cost == pytest.approx(
            6.0, abs=1e-12
        )


def _movingai_pairs(data_dir: Path) -> list[Path]:
    scens = sorted((data_dir / "movingai").glob("*.scen"))
    assert scens, "no MovingAI scenario files"
    return scens


def test_costs_equal_movingai_optimal_lengths_on_a_sample_of_every_map(
    data_dir: Path,
) -> None:
    rng = np.random.default_rng(2024)
    planner = AStar()
    checked = 0
    for scen in _movingai_pairs(data_dir):
        blocked = load_grid(scen.with_suffix(".map"))
        values = np.where(blocked, costs.LETHAL, costs.FREE).astype(np.uint8)
        scenarios = [s for s in load_scenarios(scen) if s.has_reference_length]
        sample = rng.permutation(len(scenarios))[:150]
        for index in sample:
            s = scenarios[index]
            found = planner.search(
                values, (s.start_x, s.start_y), (s.goal_x, s.goal_y), multipliers=PLAIN
            )
            assert found is not None, (scen.name, s)
            assert found.cost == pytest.approx(s.optimal_length, abs=1e-6), (scen.name, s)
            checked += 1
    assert checked > 1500


@pytest.mark.parametrize(
    "name",
    [
        "maze-32-32-4",
        "random-32-32-10",
        "room-32-32-4",
        "random-32-32-10-2",
        "maze-128-128-1",
        "maze-128-128-2",
        "lak303d",
    ],
)
def test_costs_equal_movingai_optimal_lengths_on_every_line_of_small_maps(
    data_dir: Path, name: str
) -> None:
    folder = data_dir / "movingai"
    blocked = load_grid(folder / f"{name}.map")
    values = np.where(blocked, costs.LETHAL, costs.FREE).astype(np.uint8)
    planner = AStar()
    scenarios = load_scenarios(folder / f"{name}.scen")
    reference = [s for s in scenarios if s.has_reference_length]
    assert len(reference) >= 200
    for s in reference:
        found = planner.search(
            values, (s.start_x, s.start_y), (s.goal_x, s.goal_y), multipliers=PLAIN
        )
        assert found is not None
        assert found.cost == pytest.approx(s.optimal_length, abs=1e-6), s
        _assert_valid_path(values, found.cells, PLAIN)
    # The placeholder lines of random-32-32-10-2 have true lengths 1, 2 or 3 (data README).
    for s in scenarios:
        if not s.has_reference_length:
            found = planner.search(
                values, (s.start_x, s.start_y), (s.goal_x, s.goal_y), multipliers=PLAIN
            )
            assert found is not None
            assert round(found.cost) in (1, 2, 3) and found.cost <= 3.0


def test_warehouse_scenarios_without_lengths_match_dijkstra(data_dir: Path) -> None:
    folder = data_dir / "movingai"
    blocked = load_grid(folder / "warehouse-20-40-10-2-2.map")
    values = np.where(blocked, costs.LETHAL, costs.FREE).astype(np.uint8)
    scenarios = load_scenarios(folder / "warehouse-20-40-10-2-2.scen")
    planner = AStar()
    for s in scenarios[:3]:
        reference = dijkstra_costs(values, PLAIN, (s.start_x, s.start_y))
        found = planner.search(
            values, (s.start_x, s.start_y), (s.goal_x, s.goal_y), multipliers=PLAIN
        )
        assert found is not None
        assert found.cost == pytest.approx(reference[s.goal_y, s.goal_x], abs=1e-9)
