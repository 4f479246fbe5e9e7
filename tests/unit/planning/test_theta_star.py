from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.maps import costs
from polynav.planning.astar import AStar
from polynav.planning.grid_search import step_multipliers
from polynav.planning.line_of_sight import centre_cost
from polynav.planning.theta_star import ThetaStar
from tests.unit.planning.grids import costs_from_ascii, random_costs

PLAIN = step_multipliers(cost_weight=0.0)


def test_open_ground_gives_one_straight_segment_of_euclidean_cost() -> None:
    values = np.zeros((10, 12), dtype=np.uint8)
    found = ThetaStar().search(values, (0, 0), (11, 4), multipliers=PLAIN)
    assert found is not None
    assert found.cells.tolist() == [[0, 0], [11, 4]]
    assert found.cost == pytest.approx(math.hypot(11, 4), abs=1e-12)


def test_path_bends_once_where_it_clears_the_wall() -> None:
    values = costs_from_ascii(
        """
        ......
        ......
        .###..
        ......
        """
    )
    found = ThetaStar().search(values, (0, 0), (5, 3), multipliers=PLAIN)
    assert found is not None
    # Up the free left column past the wall's end, then one segment to the goal.
    assert found.cells.tolist() == [[0, 0], [0, 2], [5, 3]]
    assert found.cost == pytest.approx(2.0 + math.hypot(5, 1), abs=1e-12)


def test_diagonal_gap_between_blocked_corners_is_closed_as_in_a_star() -> None:
    values = costs_from_ascii(
        """
        .#
        #.
        """
    )
    assert ThetaStar().search(values, (1, 0), (0, 1), multipliers=PLAIN) is None


def test_paths_are_collision_free_and_no_longer_than_a_star_on_random_maps() -> None:
    rng = np.random.default_rng(5)
    theta, astar = ThetaStar(), AStar()
    compared = 0
    for _ in range(30):
        values = np.where(rng.random((30, 40)) < 0.25, costs.LETHAL, 0).astype(np.uint8)
        free = np.argwhere(values == 0)
        (sy, sx), (gy, gx) = free[rng.choice(len(free), size=2, replace=False)]
        start, goal = (int(sx), int(sy)), (int(gx), int(gy))
        grid_path = astar.search(values, start, goal, multipliers=PLAIN)
        any_angle = theta.search(values, start, goal, multipliers=PLAIN)
        assert (grid_path is None) == (any_angle is None)
        if grid_path is None or any_angle is None:
            continue
        compared += 1
        assert any_angle.cells[0].tolist() == list(start)
        assert any_angle.cells[-1].tolist() == list(goal)
        length = 0.0
        for a, b in zip(any_angle.cells[:-1], any_angle.cells[1:], strict=True):
            segment = centre_cost(values, PLAIN, a[0], a[1], b[0], b[1])
            assert segment < math.inf
            length += segment
        assert any_angle.cost == pytest.approx(length, abs=1e-9)
        assert any_angle.cost <= grid_path.cost + 1e-9
    assert compared >= 15


def test_costly_cells_are_avoided_when_going_around_is_cheaper() -> None:
    values = costs_from_ascii(
        """
        .......
        ..999..
        ..999..
        .......
        """
    )
    table = step_multipliers(cost_weight=3.0)
    found = ThetaStar().search(values, (0, 1), (6, 1), multipliers=table)
    assert found is not None
    for a, b in zip(found.cells[:-1], found.cells[1:], strict=True):
        assert centre_cost(values, table, a[0], a[1], b[0], b[1]) < 6.0 * math.hypot(*(b - a))
    straight = centre_cost(values, table, 0, 1, 6, 1)
    assert found.cost < straight
    assert not any(values[y, x] for x, y in found.cells)


def test_weighted_random_maps_stay_within_a_star_cost_and_on_passable_cells() -> None:
    rng = np.random.default_rng(9)
    table = step_multipliers(cost_weight=2.0)
    theta = ThetaStar()
    for _ in range(10):
        values = random_costs(rng, 25, 25, blocked=0.15, costly=0.4)
        values[0, 0] = values[24, 24] = 0
        found = theta.search(values, (0, 0), (24, 24), multipliers=table)
        if found is None:
            continue
        total = sum(
            centre_cost(values, table, a[0], a[1], b[0], b[1])
            for a, b in zip(found.cells[:-1], found.cells[1:], strict=True)
        )
        assert found.cost == pytest.approx(total, abs=1e-9)


def test_impassable_start_and_escape_tables_are_refused() -> None:
    values = costs_from_ascii("I..")
    table = step_multipliers(cost_weight=1.0)
    with pytest.raises(ValueError, match="impassable"):
        ThetaStar().search(values, (0, 0), (2, 0), multipliers=table)
    with pytest.raises(ValueError, match="escape"):
        ThetaStar().search(values, (1, 0), (2, 0), multipliers=table, escape_multipliers=table)


def test_failed_search_closes_exactly_the_reachable_cells() -> None:
    values = costs_from_ascii(
        """
        .#.
        .#.
        """
    )
    theta = ThetaStar()
    assert theta.search(values, (0, 0), (2, 1), multipliers=PLAIN) is None
    assert theta.closed(np.array([[0, 0], [0, 1], [2, 0], [2, 1]])).tolist() == [
        True, True, False, False
    ]
