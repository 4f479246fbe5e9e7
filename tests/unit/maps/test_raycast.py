from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.geometry import Pose2D
from polynav.maps.map import MapInfo
from polynav.maps.raycast import cast_rays


def _wall_grid() -> tuple[np.ndarray, MapInfo]:
    occupied = np.zeros((20, 20), dtype=bool)
    occupied[:, 15] = True  # a wall whose near face is at x = 1.5 m
    return occupied, MapInfo(resolution=0.1, width=20, height=20)


def test_ray_distances_match_geometry() -> None:
    occupied, info = _wall_grid()
    angles = np.array([0.0, math.pi / 4, math.pi, math.pi / 2, -math.pi / 3])
    ranges = cast_rays(occupied, info, 0.55, 1.0, angles, 5.0)
    assert ranges[0] == pytest.approx(0.95)
    assert ranges[1] == pytest.approx(0.95 * math.sqrt(2))
    assert math.isinf(ranges[2])  # leaves the grid to the west
    assert math.isinf(ranges[3])  # leaves the grid to the north
    assert math.isinf(ranges[4])  # leaves through the south edge before reaching the wall


def test_max_range_cuts_distant_hits() -> None:
    occupied, info = _wall_grid()
    assert math.isinf(cast_rays(occupied, info, 0.55, 1.0, np.array([0.0]), 0.9)[0])
    assert cast_rays(occupied, info, 0.55, 1.0, np.array([0.0]), 0.96)[0] == pytest.approx(0.95)


def test_ray_never_skips_a_one_cell_diagonal_wall() -> None:
    occupied = np.eye(50, dtype=bool)  # a staircase wall one cell thick
    info = MapInfo(resolution=0.05, width=50, height=50)
    angles = np.linspace(-math.pi / 2 + 0.01, -0.01, 200)
    ranges = cast_rays(occupied, info, 0.3, 2.2, angles, 10.0)
    assert np.all(np.isfinite(ranges))


def test_ray_from_inside_an_obstacle_is_zero() -> None:
    occupied, info = _wall_grid()
    assert cast_rays(occupied, info, 1.55, 1.0, np.array([1.0]), 5.0)[0] == 0.0


def test_offset_origin_is_respected() -> None:
    occupied, _ = _wall_grid()
    info = MapInfo(resolution=0.1, width=20, height=20, origin=Pose2D(-1.0, -1.0, 0.0))
    assert cast_rays(occupied, info, -0.45, 0.0, np.array([0.0]), 5.0)[0] == pytest.approx(0.95)
    with pytest.raises(ValueError):
        cast_rays(occupied, MapInfo(0.1, 20, 20, Pose2D(0, 0, 0.5)), 0, 0, np.array([0.0]), 1.0)
