from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.maps import costs
from polynav.planning.grid_search import step_multipliers
from polynav.planning.line_of_sight import centre_cost, segment_cost
from tests.unit.planning.grids import costs_from_ascii, touched_cells

PLAIN = step_multipliers(cost_weight=0.0)


def test_clear_segment_costs_its_euclidean_length() -> None:
    values = np.zeros((6, 8), dtype=np.uint8)
    assert centre_cost(values, PLAIN, 0, 0, 7, 3) == pytest.approx(math.hypot(7, 3), abs=1e-12)
    assert centre_cost(values, PLAIN, 2, 5, 2, 0) == pytest.approx(5.0, abs=1e-12)


def test_cost_is_the_line_integral_of_the_step_multipliers() -> None:
    values = costs_from_ascii(".9.5")
    table = step_multipliers(cost_weight=3.0)
    # Half of the first (free) and last (cost 140) cells, all of the two middle ones.
    expected = 0.5 * 1.0 + (1 + 3.0 * 252 / 252) + 1.0 + 0.5 * (1 + 3.0 * 140 / 252)
    assert centre_cost(values, table, 0, 0, 3, 0) == pytest.approx(expected, abs=1e-12)


def test_segment_through_an_impassable_cell_costs_inf() -> None:
    values = costs_from_ascii("..I..")
    assert centre_cost(values, step_multipliers(cost_weight=1.0), 0, 0, 4, 0) == math.inf


def test_segment_exactly_through_a_corner_needs_both_side_cells() -> None:
    values = costs_from_ascii(
        """
        ...
        #..
        ...
        """
    )
    # (0, 0) -> (2, 2) passes through the corner point (1, 1), touching the blocked (0, 1).
    assert centre_cost(values, PLAIN, 0, 0, 2, 2) == math.inf
    assert centre_cost(values, PLAIN, 1, 0, 2, 1) == pytest.approx(math.sqrt(2), abs=1e-12)


def test_segment_grazing_no_corner_passes_beside_a_blocked_cell() -> None:
    values = costs_from_ascii(
        """
        ....
        #...
        ....
        """
    )
    # From the centre of (0, 0) to that of (3, 2) the segment reaches row 1 (y = 1) at x = 1.25,
    # past the blocked (0, 1): that cell is near, not touched.
    assert centre_cost(values, PLAIN, 0, 0, 3, 2) == pytest.approx(math.hypot(3, 2), abs=1e-12)


def test_segment_along_a_grid_line_touches_both_sides() -> None:
    values = costs_from_ascii(
        """
        ....
        .#..
        """
    )
    table = PLAIN
    # y = 1.0 is the line between the rows; the blocked (1, 0) lies right below it.
    assert segment_cost(values, table, 0.5, 1.0, 3.5, 1.0) == math.inf
    assert segment_cost(values, table, 0.5, 1.5, 3.5, 1.5) == pytest.approx(3.0, abs=1e-12)


def test_segment_leaving_the_grid_costs_inf() -> None:
    values = np.zeros((3, 3), dtype=np.uint8)
    assert segment_cost(values, PLAIN, 0.5, 0.5, 3.5, 0.5) == math.inf
    assert segment_cost(values, PLAIN, 0.5, 0.5, 0.5, -0.5) == math.inf


def test_zero_length_segment_costs_zero_on_a_passable_cell() -> None:
    values = costs_from_ascii(".#")
    assert segment_cost(values, PLAIN, 0.3, 0.3, 0.3, 0.3) == 0.0
    assert segment_cost(values, PLAIN, 1.3, 0.3, 1.3, 0.3) == math.inf


def test_blocking_matches_the_exact_supercover_on_random_segments() -> None:
    rng = np.random.default_rng(11)
    size = 12
    for _ in range(400):
        values = np.where(rng.random((size, size)) < 0.12, costs.LETHAL, 0).astype(np.uint8)
        x0, y0, x1, y1 = rng.uniform(0.0, size, 4)
        touched = touched_cells(x0, y0, x1, y1)
        blocked = any(values[iy, ix] == costs.LETHAL for ix, iy in touched)
        result = segment_cost(values, PLAIN, x0, y0, x1, y1)
        assert (result == math.inf) == blocked, (x0, y0, x1, y1)
        if not blocked:
            assert result == pytest.approx(math.hypot(x1 - x0, y1 - y0), abs=1e-9)


def test_blocking_matches_the_exact_supercover_between_cell_centres() -> None:
    rng = np.random.default_rng(12)
    size = 10
    for _ in range(400):
        values = np.where(rng.random((size, size)) < 0.15, costs.LETHAL, 0).astype(np.uint8)
        ax, ay, bx, by = (int(v) for v in rng.integers(0, size, 4))
        touched = touched_cells(ax + 0.5, ay + 0.5, bx + 0.5, by + 0.5)
        blocked = any(values[iy, ix] == costs.LETHAL for ix, iy in touched)
        assert (centre_cost(values, PLAIN, ax, ay, bx, by) == math.inf) == blocked
