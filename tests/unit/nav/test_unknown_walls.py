"""Unknown space that walls the robot in, told apart from walls and from a goal in the unknown."""

from __future__ import annotations

import numpy as np

from polynav.geometry import Pose2D
from polynav.maps import costs
from polynav.maps.map import MapInfo
from polynav.nav.unknown_walls import walled_in_by_unknown

INFO = MapInfo(resolution=1.0, width=10, height=3, origin=Pose2D())
START, GOAL = Pose2D(1.5, 1.5, 0.0), Pose2D(8.5, 1.5, 0.0)


def _corridor(band: int) -> np.ndarray:
    """A free 10 x 3 corridor with column 5 set to ``band``."""
    grid = np.full((3, 10), costs.FREE, dtype=np.uint8)
    grid[:, 5] = band
    return grid


def test_a_grey_band_across_the_way_walls_the_robot_in() -> None:
    assert walled_in_by_unknown(_corridor(costs.UNKNOWN), INFO, START, GOAL)


def test_a_wall_across_the_way_is_no_unknown_trap() -> None:
    assert not walled_in_by_unknown(_corridor(costs.LETHAL), INFO, START, GOAL)


def test_a_wall_behind_the_grey_band_is_no_unknown_trap() -> None:
    grid = _corridor(costs.UNKNOWN)
    grid[:, 7] = costs.LETHAL
    assert not walled_in_by_unknown(grid, INFO, START, GOAL)


def test_a_goal_in_unknown_space_is_unreachable_not_a_trap() -> None:
    grid = _corridor(costs.FREE)
    grid[:, 8:] = costs.UNKNOWN
    assert not walled_in_by_unknown(grid, INFO, START, GOAL)


def test_an_open_way_is_no_trap() -> None:
    assert not walled_in_by_unknown(_corridor(costs.FREE), INFO, START, GOAL)
