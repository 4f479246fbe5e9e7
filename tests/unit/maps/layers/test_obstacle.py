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
