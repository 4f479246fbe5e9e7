from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.maps import costs
from polynav.planning.astar import AStar
from polynav.planning.grid_search import step_multipliers
from polynav.planning.line_of_sight import centre_cost
from polynav.planning.smoothing import densify, shortcut
from tests.unit.planning.grids import costs_from_ascii, random_costs, touched_cells

PLAIN = step_multipliers(cost_weight=0.0)
WEIGHTED = step_multipliers(cost_weight=3.0)


def _staircase() -> np.ndarray:
    return np.array([[0, 0], [1, 1], [2, 2], [3, 2], [4, 2], [5, 2], [6, 3]], dtype=np.int64)


def test_open_ground_staircase_becomes_one_segment() -> None:
    values = np.zeros((5, 8), dtype=np.uint8)
    kept = shortcut(values, _staircase(), check_multipliers=PLAIN)
    assert kept.tolist() == [[0, 0], [6, 3]]


def test_shortcut_stops_at_an_obstacle_in_the_way() -> None:
    values = costs_from_ascii(
        """
        ........
        ........
        ...#....
        ........
        ........
        """
    )
    cells = np.array([[0, 2], [1, 2], [2, 1], [3, 1], [4, 1], [5, 2], [6, 2], [7, 2]])
    kept = shortcut(values, cells, check_multipliers=PLAIN)
    assert kept[0].tolist() == [0, 2] and kept[-1].tolist() == [7, 2]
    assert 3 <= kept.shape[0] < cells.shape[0]
    for a, b in zip(kept[:-1], kept[1:], strict=True):
        assert centre_cost(values, PLAIN, a[0], a[1], b[0], b[1]) < math.inf


def test_inscribed_cells_are_never_entered_by_a_shortcut() -> None:
    rng = np.random.default_rng(21)
    planner = AStar()
    checked = 0
    for _ in range(40):
        values = random_costs(rng, 30, 30, blocked=0.06, costly=0.3)
        # Make blobs of inscribed cells: a cell next to a lethal one is inscribed.
        lethal = values == costs.LETHAL
        near = np.zeros_like(lethal)
        near[1:, :] |= lethal[:-1, :]
        near[:-1, :] |= lethal[1:, :]
        near[:, 1:] |= lethal[:, :-1]
        near[:, :-1] |= lethal[:, 1:]
        values[near & ~lethal] = costs.INSCRIBED
        values[0, 0] = values[29, 29] = 0
        found = planner.search(values, (0, 0), (29, 29), multipliers=WEIGHTED)
        if found is None:
            continue
        kept = shortcut(values, found.cells, check_multipliers=WEIGHTED)
        for a, b in zip(kept[:-1], kept[1:], strict=True):
            for ix, iy in touched_cells(a[0] + 0.5, a[1] + 0.5, b[0] + 0.5, b[1] + 0.5):
                assert values[iy, ix] < costs.INSCRIBED, (a, b, (ix, iy))
        checked += 1
    assert checked >= 10


def test_a_shortcut_across_costly_cells_needs_a_looser_cost_ratio() -> None:
    values = costs_from_ascii(
        """
        .......
        .99999.
        .......
        """
    )
    # Around the costly band: up, across, down.
    cells = np.array([[0, 1], [0, 2], [1, 2], [2, 2], [3, 2], [4, 2], [5, 2], [6, 2], [6, 1]])
    kept = shortcut(values, cells, check_multipliers=WEIGHTED)
    assert kept.tolist() != [[0, 1], [6, 1]]
    for a, b in zip(kept[:-1], kept[1:], strict=True):
        assert not any(values[iy, ix] for ix, iy in touched_cells(a[0] + .5, a[1] + .5,
                                                                   b[0] + .5, b[1] + .5))
    loose = shortcut(values, cells, check_multipliers=WEIGHTED, max_cost_ratio=10.0)
    assert loose.tolist() == [[0, 1], [6, 1]]


def test_escape_segments_through_inscribed_cells_are_kept() -> None:
    values = costs_from_ascii(
        """
        ......
        ..I...
        II....
        """
    )
    escape = step_multipliers(cost_weight=3.0, escape_below=costs.LETHAL)
    cells = np.array([[0, 0], [1, 0], [2, 1], [3, 2], [4, 2], [5, 2]])
    kept = shortcut(values, cells, check_multipliers=WEIGHTED, measure_multipliers=escape)
    # Nothing leaves an inscribed vertex in a new straight line: the escape keeps its shape
    # ((1, 0) -> (3, 2) is the original diagonal run), and only the free tail could change.
    assert kept.tolist() == [[0, 0], [1, 0], [3, 2], [5, 2]]


def test_short_paths_are_returned_unchanged() -> None:
    values = np.zeros((2, 2), dtype=np.uint8)
    for cells in ([[0, 0]], [[0, 0], [1, 1]]):
        kept = shortcut(values, np.array(cells), check_multipliers=PLAIN)
        assert kept.tolist() == cells


def test_a_cost_ratio_below_one_is_refused() -> None:
    with pytest.raises(ValueError):
        shortcut(np.zeros((2, 2), np.uint8), _staircase(), check_multipliers=PLAIN,
                 max_cost_ratio=0.9)


def test_densify_spaces_points_evenly_within_each_segment_and_keeps_vertices() -> None:
    points = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 0.12]])
    out = densify(points, 0.3)
    assert out[0].tolist() == [0.0, 0.0] and out[-1].tolist() == [1.0, 0.12]
    # 1.0 m in four parts of 0.25 m, then 0.12 m in one part.
    assert np.allclose(out[:, 0], [0.0, 0.25, 0.5, 0.75, 1.0, 1.0])
    assert np.allclose(out[:, 1], [0.0, 0.0, 0.0, 0.0, 0.0, 0.12])
    steps = np.hypot(*np.diff(out, axis=0).T)
    assert steps.max() <= 0.3 + 1e-12


def test_densify_keeps_exact_multiples_without_an_extra_point() -> None:
    out = densify(np.array([[0.0, 0.0], [0.15, 0.0]]), 0.05)
    assert out.shape == (4, 2)
    assert np.allclose(out[:, 0], [0.0, 0.05, 0.10, 0.15])


def test_densify_with_zero_spacing_or_one_point_copies() -> None:
    points = np.array([[0.0, 0.0], [2.0, 0.0]])
    out = densify(points, 0.0)
    assert out.tolist() == points.tolist() and out is not points
    assert densify(np.array([[1.0, 2.0]]), 0.1).tolist() == [[1.0, 2.0]]


def test_densify_refuses_a_negative_spacing() -> None:
    with pytest.raises(ValueError):
        densify(np.zeros((2, 2)), -0.1)
