from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.geometry import Pose2D
from polynav.maps.map import Map, MapInfo


def test_world_to_cell_and_back_with_offset_origin() -> None:
    info = MapInfo(resolution=0.05, width=100, height=50, origin=Pose2D(-2.0, -1.0, 0.0))
    assert info.world_to_cell(-2.0, -1.0) == (0, 0)
    assert info.world_to_cell(-1.951, -0.951) == (0, 0)
    assert info.world_to_cell(-1.949, -0.949) == (1, 1)
    assert info.world_to_cell(-2.001, 0.0) == (-1, 20)
    assert info.cell_to_world(0, 0) == pytest.approx((-1.975, -0.975))
    assert not info.contains(-1, 20)
    assert info.contains(99, 49)
    assert not info.contains(100, 49)


def test_rotated_origin_conversions_agree_with_vectorised_forms() -> None:
    info = MapInfo(resolution=0.1, width=30, height=20, origin=Pose2D(1.0, 2.0, math.pi / 2))
    cells = np.array([[0, 0], [5, 7], [29, 19]])
    world = info.cells_to_world(cells)
    for (ix, iy), (x, y) in zip(cells, world, strict=True):
        assert info.cell_to_world(ix, iy) == pytest.approx((x, y))
        assert info.world_to_cell(x, y) == (ix, iy)
    assert np.array_equal(info.world_to_cells(world), cells)
    # With a quarter turn, the grid's +x runs along world +y.
    assert info.cell_to_world(0, 0) == pytest.approx((0.95, 2.05))


def test_map_rejects_data_of_the_wrong_shape() -> None:
    with pytest.raises(ValueError):
        Map(MapInfo(1.0, 3, 2), np.zeros((3, 2), dtype=np.int8))


def test_from_occupied_and_free_queries() -> None:
    occupied = np.array([[False, True], [False, False]])
    grid = Map.from_occupied(occupied, resolution=1.0)
    assert grid.data.tolist() == [[0, 100], [0, 0]]
    assert grid.is_free_at(0.5, 0.5)
    assert not grid.is_free_at(1.5, 0.5)
    assert not grid.is_free_at(-0.5, 0.5)


def test_cells_within_are_those_whose_centres_are_in_the_disc_and_on_the_grid() -> None:
    info = MapInfo(resolution=0.1, width=20, height=10, origin=Pose2D(1.0, 2.0, 0.0))
    cells = info.cells_within(1.55, 2.55, 0.15)  # the centre of cell (5, 5)
    assert {tuple(c) for c in cells} == {(5, 5), (4, 5), (6, 5), (5, 4), (5, 6),
                                         (4, 4), (4, 6), (6, 4), (6, 6)}
    corner = info.cells_within(1.0, 2.0, 0.3)  # the grid's corner: no cell off the grid
    assert len(corner) and (corner >= 0).all()
    centres = info.cells_to_world(corner)
    assert (np.hypot(centres[:, 0] - 1.0, centres[:, 1] - 2.0) <= 0.3).all()
    assert info.cells_within(-5.0, -5.0, 1.0).shape == (0, 2)
