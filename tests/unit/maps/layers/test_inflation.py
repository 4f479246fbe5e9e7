from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import ndimage

from polynav.geometry import Pose2D
from polynav.maps import costs
from polynav.maps.layers.inflation import InflationLayer, inflation_cost, squared_distances
from polynav.maps.map import MapInfo

RADII = {"robot_radius": 0.25, "inflation_radius": 0.55, "cost_scaling_factor": 3.0}


@pytest.mark.parametrize(
    ("distance", "cost"),
    [
        (0.0, costs.LETHAL),
        (0.05, 253),
        (0.25, 253),
        (0.3, 216),
        (0.4, 160),
        (0.55, 102),
        (0.5500001, 0),
        (3.0, 0),
    ],
)
def test_inflation_cost_matches_nav2_compute_cost(distance: float, cost: int) -> None:
    assert inflation_cost(distance, **RADII) == cost


def test_inflation_reaches_ceil_of_radius_in_cells() -> None:
    layer = InflationLayer(MapInfo(resolution=0.05, width=50, height=50), **RADII)
    assert layer.cell_radius == 11
    layer = InflationLayer(MapInfo(resolution=0.1, width=50, height=50), **RADII)
    assert layer.cell_radius == 6


def test_update_bounds_grows_the_window_by_the_radius_within_the_grid() -> None:
    layer = InflationLayer(MapInfo(resolution=0.05, width=50, height=40), **RADII)
    assert layer.update_bounds(Pose2D(), None) is None
    assert layer.update_bounds(Pose2D(), (20, 5, 22, 6)) == (9, 0, 33, 17)


def test_lethal_cell_outside_the_write_window_still_inflates_inside_it() -> None:
    info = MapInfo(resolution=0.05, width=40, height=1)
    layer = InflationLayer(info, **RADII)
    master = np.zeros((1, 40), dtype=np.uint8)
    master[0, 5] = costs.LETHAL
    layer.update_costs(master, (10, 0, 20, 1))
    # Cells 10..16 are 5..11 cells from the obstacle; cells outside the window are untouched.
    assert master[0, 10:20].tolist() == [253, 216, 186, 160, 138, 119, 102, 0, 0, 0]
    assert master[0, 6:10].tolist() == [0, 0, 0, 0]


def test_inflation_never_lowers_a_cost() -> None:
    info = MapInfo(resolution=0.05, width=10, height=1)
    master = np.array([[costs.LETHAL, 250, costs.UNKNOWN, 0, 0, 0, 0, 240, 0, 0]], dtype=np.uint8)
    InflationLayer(info, **RADII).update_costs(master, (0, 0, 10, 1))
    assert master[0].tolist() == [254, 253, 255, 253, 253, 253, 216, 240, 160, 138]


def test_zero_inflation_radius_leaves_the_master_alone() -> None:
    info = MapInfo(resolution=0.05, width=3, height=1)
    master = np.array([[costs.LETHAL, 0, 0]], dtype=np.uint8)
    layer = InflationLayer(info, robot_radius=0.0, inflation_radius=0.0, cost_scaling_factor=3.0)
    layer.update_costs(master, (0, 0, 3, 1))
    assert master[0].tolist() == [254, 0, 0]
    assert math.isclose(
        inflation_cost(0.05, robot_radius=0.0, inflation_radius=0.0, cost_scaling_factor=3.0), 0
    )


@pytest.mark.parametrize("density", [0.0005, 0.02, 0.3, 0.9])
def test_squared_distances_equal_scipy_euclidean_distance_transform(density: float) -> None:
    rng = np.random.default_rng(11)
    lethal = rng.random((67, 91)) < density
    lethal[3, 5] = True  # at least one
    expected = ndimage.distance_transform_edt(~lethal) ** 2
    np.testing.assert_array_equal(squared_distances(lethal), np.rint(expected).astype(np.int64))


def test_squared_distances_on_a_single_cell_and_a_single_row() -> None:
    assert squared_distances(np.array([[True]])).tolist() == [[0]]
    row = np.array([[False, True, False, False]])
    assert squared_distances(row).tolist() == [[1, 0, 1, 4]]


def test_squared_distances_without_lethal_cells_are_farther_than_the_grid() -> None:
    d2 = squared_distances(np.zeros((4, 6), dtype=bool))
    assert (d2 >= (4 + 6) ** 2).all()


@pytest.mark.parametrize("density", [0.002, 0.02, 0.2])
def test_a_window_is_inflated_exactly_as_scipys_transform_says(density: float) -> None:
    rng = np.random.default_rng(3)
    info = MapInfo(resolution=0.05, width=90, height=70)
    layer = InflationLayer(info, **RADII)
    master = np.zeros((70, 90), dtype=np.uint8)
    master[rng.random((70, 90)) < density] = costs.LETHAL
    master[rng.random((70, 90)) < 0.05] = 40  # costs below stay where inflation is lower
    distance = ndimage.distance_transform_edt(master != costs.LETHAL) * info.resolution
    expected = master.copy()
    window = (17, 9, 61, 50)
    for y in range(window[1], window[3]):
        for x in range(window[0], window[2]):
            expected[y, x] = max(master[y, x], inflation_cost(float(distance[y, x]), **RADII))
    layer.update_costs(master, window)
    np.testing.assert_array_equal(master, expected)
