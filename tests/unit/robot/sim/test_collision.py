from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.maps.ascii import map_from_ascii
from polynav.robot.sim.collision import person_clearance, wall_clearance

# One occupied cell at x 1.5..2.0, y 1.0..1.5, in a 3 m x 2.5 m grid of 0.5 m cells.
GRID = map_from_ascii(
    """
    ......
    ......
    ...#..
    ......
    ......
    """,
    resolution=0.5,
)


def _gap(x: float, y: float, radius: float = 0.2, horizon: float = 5.0) -> float:
    return wall_clearance(GRID.occupied(), GRID.info, x, y, radius=radius, horizon=horizon)


def test_gap_to_a_cell_face_and_to_a_cell_corner() -> None:
    assert _gap(1.0, 1.25) == pytest.approx(0.5 - 0.2)  # west of the cell, level with it
    assert _gap(1.75, 1.8) == pytest.approx(0.3 - 0.2)  # above it
    assert _gap(1.2, 0.7) == pytest.approx(math.hypot(0.3, 0.3) - 0.2)  # off its SW corner


def test_overlap_is_negative_and_a_centre_inside_is_minus_the_radius() -> None:
    assert _gap(1.4, 1.25) == pytest.approx(-0.1)
    assert _gap(1.7, 1.3) == pytest.approx(-0.2)


def test_the_grid_edge_is_a_wall() -> None:
    assert _gap(0.3, 1.25) == pytest.approx(0.3 - 0.2)


def test_gaps_beyond_the_horizon_read_as_the_horizon() -> None:
    big = map_from_ascii("." * 40 + "\n" + "." * 40, resolution=0.5)
    gap = wall_clearance(big.occupied(), big.info, 10.0, 0.5, radius=0.2, horizon=0.1)
    assert gap == pytest.approx(0.1)


def test_person_clearance_is_the_gap_between_circles() -> None:
    people = np.array([[2.0, 0.0, 0.25], [0.0, 3.0, 0.3]])
    assert person_clearance(0.0, 0.0, 0.25, people) == pytest.approx(1.5)
    assert person_clearance(1.7, 0.0, 0.25, people) == pytest.approx(-0.2)
    assert math.isinf(person_clearance(0.0, 0.0, 0.25, np.empty((0, 3))))
