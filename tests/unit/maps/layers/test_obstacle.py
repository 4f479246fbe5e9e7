from __future__ import annotations

import math

import numpy as np

from polynav.geometry import Pose2D
from polynav.maps import costs
from polynav.maps.layers.obstacle import ObstacleLayer, warm_up
from polynav.maps.map import MapInfo
from polynav.robot.interface import LaserScan

INFO = MapInfo(resolution=0.1, width=30, height=20)


def layer() -> ObstacleLayer:
    return ObstacleLayer(INFO, obstacle_max_range=6.0, raytrace_max_range=8.0)


def beam(r: float, angle: float = 0.0) -> LaserScan:
    return LaserScan(0.0, angle, 0.01, 0.05, 10.0, np.array([r], dtype=np.float32))


def test_layer_starts_with_no_information() -> None:
    assert (layer().grid == costs.UNKNOWN).all()


def test_add_scan_returns_the_window_of_cells_that_changed() -> None:
    obstacles = layer()
    changed = obstacles.add_scan(Pose2D(0.55, 0.55, 0.0), beam(1.0))
    assert changed == (5, 5, 16, 6)
    assert obstacles.grid[5, 5:15].tolist() == [costs.FREE] * 10
    assert obstacles.grid[5, 15] == costs.LETHAL
    assert obstacles.add_scan(Pose2D(0.55, 0.55, 0.0), beam(1.0)) is None


def test_update_bounds_reports_pending_changes_once() -> None:
    obstacles = layer()
    obstacles.add_scan(Pose2D(0.55, 0.55, 0.0), beam(0.3))
    assert obstacles.update_bounds(Pose2D(), None) == (5, 5, 9, 6)
    assert obstacles.update_bounds(Pose2D(), None) is None
    assert obstacles.update_bounds(Pose2D(), (0, 0, 1, 1)) == (0, 0, 1, 1)


def test_clear_forgets_everything_and_dirties_what_was_touched() -> None:
    obstacles = layer()
    obstacles.add_scan(Pose2D(0.55, 0.55, 0.0), beam(0.3))
    obstacles.add_scan(Pose2D(0.55, 1.55, math.pi / 2), beam(0.2))
    obstacles.update_bounds(Pose2D(), None)
    obstacles.clear()
    assert (obstacles.grid == costs.UNKNOWN).all()
    assert obstacles.update_bounds(Pose2D(), None) == (5, 5, 9, 18)


def test_beam_leaving_the_grid_is_clipped() -> None:
    obstacles = layer()
    obstacles.add_scan(Pose2D(2.55, 0.55, 0.0), beam(3.0))
    assert obstacles.grid[5, 25:].tolist() == [costs.FREE] * 5
    assert np.count_nonzero(obstacles.grid == costs.LETHAL) == 0


def test_robot_outside_the_grid_still_marks_and_clears_inside_it() -> None:
    obstacles = layer()
    obstacles.add_scan(Pose2D(-0.45, 0.55, 0.0), beam(1.0))
    assert obstacles.grid[5, 0:5].tolist() == [costs.FREE] * 5
    assert obstacles.grid[5, 5] == costs.LETHAL


def test_warm_up_compiles_without_error() -> None:
    warm_up()


def test_range_noise_keeps_a_return_from_clearing_the_cell_just_in_front_of_it() -> None:
    # The face of a post at x = 1.50 m (the boundary between cells 14 and 15). One scan's short
    # return (1.49 m from the sensor at 0.0) marks cell 14; the next scan's longer return (1.51 m)
    # passes through cell 14 but within 3 sigma of its own end: cell 14 stays marked.
    noisy = ObstacleLayer(INFO, obstacle_max_range=6.0, raytrace_max_range=8.0, range_noise=0.01)
    noisy.add_scan(Pose2D(0.0, 0.55, 0.0), beam(1.49))
    assert noisy.grid[5, 14] == costs.LETHAL
    noisy.add_scan(Pose2D(0.0, 0.55, 0.0), beam(1.51))
    assert noisy.grid[5, 14] == costs.LETHAL and noisy.grid[5, 15] == costs.LETHAL
    assert noisy.grid[5, 0:14].tolist() == [costs.FREE] * 14
    # Without the noise model the same two scans flicker the cell free again.
    exact = ObstacleLayer(INFO, obstacle_max_range=6.0, raytrace_max_range=8.0, range_noise=0.0)
    exact.add_scan(Pose2D(0.0, 0.55, 0.0), beam(1.49))
    exact.add_scan(Pose2D(0.0, 0.55, 0.0), beam(1.51))
    assert exact.grid[5, 14] == costs.FREE


def test_a_beam_passing_well_clear_still_clears_a_stale_mark() -> None:
    obstacles = layer()
    obstacles.add_scan(Pose2D(0.0, 0.55, 0.0), beam(1.49))
    assert obstacles.grid[5, 14] == costs.LETHAL
    obstacles.add_scan(Pose2D(0.0, 0.55, 0.0), beam(2.5))
    assert obstacles.grid[5, 14] == costs.FREE


def test_clear_around_forgets_only_the_marks_near_the_point() -> None:
    obstacles = layer()
    obstacles.add_scan(Pose2D(0.55, 0.55, 0.0), beam(0.5))  # marks (10, 5)
    obstacles.add_scan(Pose2D(0.55, 1.55, 0.0), beam(2.0))  # marks (25, 15)
    obstacles.update_bounds(Pose2D(), None)
    window = obstacles.clear_around(1.0, 0.5, 0.3)
    assert window is not None
    assert obstacles.grid[5, 10] == costs.UNKNOWN
    assert obstacles.grid[15, 25] == costs.LETHAL
    assert obstacles.update_bounds(Pose2D(), None) == window
    assert obstacles.clear_around(1.0, 0.5, 0.3) is None  # nothing left to forget there


def test_passable_cells_are_never_marked_and_forget_their_marks() -> None:
    obstacles = layer()
    obstacles.add_scan(Pose2D(0.55, 0.55, 0.0), beam(1.0))
    assert obstacles.grid[5, 15] == costs.LETHAL
    door = np.zeros((INFO.height, INFO.width), dtype=np.bool_)
    door[:, 15] = True  # a door's leaf across the beam
    assert obstacles.set_passable(door) == (15, 5, 16, 6)
    assert obstacles.grid[5, 15] == costs.UNKNOWN
    assert obstacles.update_bounds(Pose2D(), None) == (5, 5, 16, 6)
    obstacles.add_scan(Pose2D(0.55, 0.55, 0.0), beam(1.0))
    assert obstacles.grid[5, 15] == costs.UNKNOWN  # the leaf is seen, not kept
    assert obstacles.grid[5, 5:15].tolist() == [costs.FREE] * 10  # the way to it is cleared
    other = obstacles.add_scan(Pose2D(0.55, 0.55, 0.0), beam(0.5))
    assert other is not None and obstacles.grid[5, 10] == costs.LETHAL  # elsewhere: marked
    assert obstacles.set_passable(None) is None
    obstacles.add_scan(Pose2D(0.55, 0.55, 0.0), beam(1.0))
    assert obstacles.grid[5, 15] == costs.LETHAL
