"""The door rule's geometry: where a path crosses a door, and the cells the lidar leaves alone."""

from __future__ import annotations

import numpy as np
import pytest

from polynav.errors import ConfigError
from polynav.geometry import Pose2D
from polynav.maps.map import MapInfo
from polynav.runtime.door_passage import DoorConfig, _crossing, passable_mask
from polynav.worlds.world import WorldDoor

DOOR = WorldDoor("d", "f", 5.0, -1.0, 5.0, 1.0)


def _line(x0: float, x1: float) -> np.ndarray:
    xs = np.arange(x0, x1 + 1e-9, 0.05)
    return np.column_stack((xs, np.zeros_like(xs)))


def test_a_door_ahead_is_found_at_its_distance_along_the_path() -> None:
    path = _line(2.0, 9.0)
    assert _crossing(path, 0, DOOR, 4.0, Pose2D(2.0, 0.0)) == pytest.approx(3.0)
    # Further than the lookahead: not yet.
    assert _crossing(path, 0, DOOR, 2.5, Pose2D(2.0, 0.0)) is None
    # The robot off the path's start: measured from its nearest point.
    assert _crossing(path, 20, DOOR, 4.0, Pose2D(3.0, 0.1)) == pytest.approx(2.1, abs=0.01)


def test_a_door_behind_or_beside_the_path_is_not_ahead() -> None:
    path = _line(5.1, 9.0)
    assert _crossing(path, 0, DOOR, 4.0, Pose2D(4.9, 0.0)) is None  # just passed
    beside = np.column_stack((np.full(50, 4.0), np.linspace(-3.0, 3.0, 50)))
    assert _crossing(beside, 0, DOOR, 10.0, Pose2D(4.0, -3.0)) is None


def test_passable_cells_lie_along_the_leaf_only() -> None:
    info = MapInfo(resolution=0.1, width=100, height=40, origin=Pose2D(0.0, -2.0, 0.0))
    mask = passable_mask([DOOR], info)
    ix, iy = info.world_to_cell(5.0, 0.0)
    assert mask[iy, ix] and mask[info.world_to_cell(5.0, 0.95)[1], ix]
    assert not mask[iy, info.world_to_cell(5.5, 0.0)[0]]
    assert not mask[info.world_to_cell(5.0, 1.5)[1], ix]
    assert 40 <= int(mask.sum()) <= 90


def test_config_is_checked() -> None:
    with pytest.raises(ConfigError):
        DoorConfig(stop_distance=5.0)
    with pytest.raises(ConfigError):
        DoorConfig(open_timeout=0.0)
