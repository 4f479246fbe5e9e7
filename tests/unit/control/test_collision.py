from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.control import collision
from polynav.geometry import Pose2D
from polynav.maps import costs
from tests.unit.control.unicycle import empty_grid

INS, L, U = costs.INSCRIBED, costs.LETHAL, costs.UNKNOWN


def test_costs_are_read_under_points_and_unknown_off_the_grid() -> None:
    grid = empty_grid(size_m=2.0, resolution=0.5)  # cells of 0.5 m from (-1, -1)
    grid.costs[:] = [[1, 2, 3, 4], [5, 6, 7, 8], [9, 10, 11, 12], [13, 14, 15, 16]]
    pts = np.array([[-0.9, -0.9], [0.6, -0.9], [-0.9, 0.6], [0.1, 0.1], [1.5, 0.0]])
    assert collision.costs_at(grid, pts).tolist() == [1, 4, 13, 11, U]
    assert collision.cost_at(grid, 0.6, 0.6) == 16
    assert collision.cost_at(grid, -1.1, 0.0) == U


@pytest.mark.parametrize(
    ("values", "expected"),
    [
        ([0, 0, 100, 252, 0], None),
        ([0, 0, INS, 0], 2),
        ([0, L, INS], 1),
        ([U, U, 0], None),
        ([INS, INS, 0, 0, L], 4),  # starting inside: only a hit after leaving counts
        ([L, INS, L], None),  # inside all along
        ([], None),
    ],
)
def test_first_collision(values: list[int], expected: int | None) -> None:
    assert collision.first_collision(np.array(values, dtype=np.int64)) == expected


def test_arc_points_follow_a_circle() -> None:
    # Radius 1 about (0, 2): turning left from (1, 2) heading +y, a quarter turn ends at (0, 3).
    pts = collision.arc_points(Pose2D(1.0, 2.0, math.pi / 2), 1.0, math.pi / 2, 0.05)
    assert pts[0] == pytest.approx([1.0, 2.0])
    assert pts[-1] == pytest.approx([0.0, 3.0])
    assert np.hypot(pts[:, 0], pts[:, 1] - 2.0) == pytest.approx(np.ones(len(pts)))
    assert np.max(np.hypot(*np.diff(pts, axis=0).T)) <= 0.05


def test_arc_points_straight() -> None:
    pts = collision.arc_points(Pose2D(0.0, 0.0, 0.0), 0.0, 1.0, 0.25)
    assert pts.tolist() == [[0.0, 0.0], [0.25, 0.0], [0.5, 0.0], [0.75, 0.0], [1.0, 0.0]]


def test_arc_poses_carry_the_heading_along_the_arc() -> None:
    poses = collision.arc_poses(Pose2D(0.0, 0.0, 0.5), 2.0, 1.0, 0.3)
    assert poses.shape == (5, 3)  # ceil(1.0 / 0.3) = 4 steps, both ends included
    assert poses[0].tolist() == [0.0, 0.0, 0.5]
    assert poses[:, 2] == pytest.approx(0.5 + 2.0 * np.linspace(0.0, 1.0, 5))
    # Every point lies on the circle of radius 1/kappa about the turn's centre.
    centre = np.array([-math.sin(0.5), math.cos(0.5)]) / 2.0
    assert np.hypot(*(poses[:, :2] - centre).T) == pytest.approx(0.5)
