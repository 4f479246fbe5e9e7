"""Frontier exploration: in a small two-room world the robot maps both rooms on its own, comes
back to where it began and says so; the map it saved lets it navigate."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

from polynav.errors import Conflict
from polynav.geometry import Pose2D
from polynav.maps.map import Map, MapInfo
from polynav.runtime.config import Mode, RuntimeConfig
from polynav.runtime.exploration import frontiers
from polynav.runtime.robot_runtime import RobotRuntime
from polynav.store.site_store import SiteStore
from tests.helpers.worlds import TWO_ROOMS_START, two_rooms

START = TWO_ROOMS_START


@pytest.fixture
def runtime(tmp_path: Path) -> Iterator[RobotRuntime]:
    world = two_rooms()
    with SiteStore.open(tmp_path / "data", seed_world=world) as store:
        yield RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False, seed=2))


def test_frontiers_are_free_cells_beside_unknown_ones() -> None:
    data = np.full((10, 10), -1, dtype=np.int8)
    data[2:8, 2:5] = 0  # a known strip, unknown all round
    data[2:8, 5] = 100  # a wall on its right side
    found = frontiers(Map(MapInfo(1.0, 10, 10), data), np.ones((10, 10), dtype=bool), 1)
    cells = {tuple(c) for cluster in found for c in cluster}
    assert (2, 2) in cells and (3, 7) in cells  # its unknown-facing rims
    assert (3, 4) not in cells  # inside
    assert all(data[iy, ix] == 0 for ix, iy in cells)


def test_the_robot_explores_both_rooms_comes_back_and_the_map_is_usable(
    runtime: RobotRuntime,
) -> None:
    with pytest.raises(Conflict):
        runtime.explore()  # not mapping
    sub = runtime.bus.subscribe()
    runtime.start_mapping()
    runtime.advance(0.5)
    runtime.explore()
    with pytest.raises(Conflict, match="already exploring"):
        runtime.explore()
    done = runtime.advance_until(
        lambda: any(e.kind == "exploration_finished" for e in sub.get_nowait()), 600.0)
    assert done, runtime.status()
    assert runtime.simulation.true_pose.distance_to(START) <= 0.6  # back where it began
    assert runtime.simulation.collisions == []
    grid = runtime.mapping_map()
    east = grid.info.world_to_cell(9.5, 3.0)
    assert grid.data[east[1], east[0]] == 0  # the far room is mapped free
    runtime.stop_mapping("explored")
    assert runtime.mode is Mode.FREE
    runtime.start_navigation("explored", pose=runtime.status().pose)
    runtime.advance(1.0)
    runtime.go_to(pose=Pose2D(9.5, 3.0, 0.0))
    assert runtime.advance_until(lambda: runtime.status().navigation_state != "running", 120.0)
    assert runtime.status().navigation_state == "succeeded"
    assert runtime.simulation.true_pose.distance_to(Pose2D(9.5, 3.0, 0.0)) <= 0.3
