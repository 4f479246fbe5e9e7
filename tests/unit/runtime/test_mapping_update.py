"""Updating (extending) a saved map: the robot is localized on it (relocalization, a point, or
its navigation estimate), what it sees is added in the map's own frame, the result is saved
under the same or a new name and navigated on."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest
from scipy import ndimage

from polynav.errors import Conflict, InvalidRequest, NotFound
from polynav.geometry import Pose2D
from polynav.maps.map import Map
from polynav.runtime.config import Mode, RuntimeConfig
from polynav.runtime.robot_runtime import RobotRuntime
from polynav.store.site_store import SiteStore
from polynav.worlds import load_world

WORLD = load_world("demo")
TRUTH = WORLD.floor("floor1").map
# The west part of the lobby is cut out of the saved map: the robot has to add it.
CUT_X, CUT_Y = 4.5, 11.0


def _cut(grid: Map) -> Map:
    data = grid.data.copy()
    xs = grid.info.origin.x + (np.arange(grid.info.width) + 0.5) * grid.info.resolution
    ys = grid.info.origin.y + (np.arange(grid.info.height) + 0.5) * grid.info.resolution
    region = (xs[None, :] < CUT_X) & (ys[:, None] < CUT_Y)
    data[region] = -1
    return Map(grid.info, data)


@pytest.fixture
def runtime(tmp_path: Path) -> Iterator[RobotRuntime]:
    with SiteStore.open(tmp_path / "data", seed_world=WORLD) as store:
        store.save_map("partial", _cut(TRUTH), floor="floor1")
        yield RobotRuntime.simulated(store, WORLD, config=RuntimeConfig(people=False, seed=5))


def _drive(runtime: RobotRuntime, linear: float, angular: float, seconds: float) -> None:
    for _ in range(round(seconds / 0.2)):
        runtime.teleop(linear, angular)
        runtime.advance(0.2)


def _region(grid: Map) -> np.ndarray:
    """Cells of ``grid`` inside the cut, as a mask."""
    info = grid.info
    xs = info.origin.x + (np.arange(info.width) + 0.5) * info.resolution
    ys = info.origin.y + (np.arange(info.height) + 0.5) * info.resolution
    return (xs[None, :] < CUT_X) & (ys[:, None] < CUT_Y)


def _truth_at(grid: Map) -> np.ndarray:
    """The ground truth sampled at ``grid``'s cell centres (-1 outside it)."""
    info = grid.info
    xs = info.origin.x + (np.arange(info.width) + 0.5) * info.resolution
    ys = info.origin.y + (np.arange(info.height) + 0.5) * info.resolution
    t = TRUTH.info
    ix = np.floor((xs - t.origin.x) / t.resolution).astype(int)
    iy = np.floor((ys - t.origin.y) / t.resolution).astype(int)
    inside = (ix[None, :] >= 0) & (ix[None, :] < t.width) & (iy[:, None] >= 0) & (
        iy[:, None] < t.height)
    out = np.full((info.height, info.width), -1, dtype=np.int8)
    gx, gy = np.broadcast_arrays(ix[None, :], iy[:, None])
    out[inside] = TRUTH.data[gy[inside], gx[inside]]
    return out


def test_an_extended_map_keeps_its_frame_gains_the_new_area_and_is_navigated_on(
    runtime: RobotRuntime,
) -> None:
    with pytest.raises(Conflict, match="no scan yet"):
        runtime.start_mapping("partial")  # just powered on: nothing to find it by
    runtime.advance(0.2)
    runtime.start_mapping("partial")  # found by global relocalization
    assert runtime.mode is Mode.MAPPING
    runtime.advance(0.5)
    assert runtime.status().pose.distance_to(runtime.simulation.true_pose) < 0.1
    # Into the cut: face south, 2 m down, face west, 3 m on, below the lobby's shelves.
    _drive(runtime, 0.0, -0.6, 2.6)
    _drive(runtime, 0.4, 0.0, 5.0)
    _drive(runtime, 0.0, -0.6, 2.6)
    _drive(runtime, 0.4, 0.0, 8.0)
    # The pose on the map being extended is the pose in the map's (the world's) frame.
    assert runtime.status().pose.distance_to(runtime.simulation.true_pose) < 0.1
    record = runtime.stop_mapping("partial")  # its own name: no overwrite needed
    assert runtime.mode is Mode.FREE and record.floor == "floor1"  # type: ignore[attr-defined]
    grid = runtime.store.load_map("partial")
    truth = _truth_at(grid)
    cut = _region(grid)
    # What was known stays known, where it was: the far east rooms were never seen this time.
    east = grid.info.world_to_cell(34.6, 4.8)
    assert grid.data[east[1], east[0]] == 0
    # The cut is mapped again: most of its free area free, its walls on true walls.
    free_truth = cut & (truth == 0)
    # (the shelves shade a few strips)
    assert np.count_nonzero(grid.data[free_truth] == 0) >= 0.7 * np.count_nonzero(free_truth)
    walls = cut & (grid.data == 100)
    near_wall = ndimage.binary_dilation(truth == 100, structure=np.ones((3, 3), dtype=bool))
    assert np.count_nonzero(walls) > 200
    assert np.count_nonzero(near_wall[walls]) >= 0.95 * np.count_nonzero(walls)
    # Navigate on it into the area it gained.
    runtime.start_navigation("partial")
    runtime.advance(1.0)
    goal = Pose2D(2.0, 5.5, 0.0)
    runtime.go_to(pose=goal)
    assert runtime.advance_until(lambda: runtime.status().navigation_state != "running", 90.0)
    assert runtime.status().navigation_state == "succeeded"
    assert runtime.simulation.true_pose.distance_to(goal) <= 0.3


def test_updating_while_navigating_on_the_map_starts_from_its_estimate(
    runtime: RobotRuntime,
) -> None:
    runtime.start_navigation("partial")
    runtime.advance(1.0)
    with pytest.raises(Conflict, match="starts from free"):
        runtime.start_mapping("floor1")  # another map than the one navigated on
    runtime.start_mapping("partial")
    assert runtime.mode is Mode.MAPPING and runtime.map_name is None
    runtime.advance(0.5)
    assert runtime.status().pose.distance_to(runtime.simulation.true_pose) < 0.1
    with pytest.raises(Conflict, match="exists"):
        runtime.save_mapping("floor1")  # another map's name still needs overwrite
    runtime.save_mapping("partial_v2")
    assert runtime.mode is Mode.MAPPING
    runtime.cancel_mapping()


def test_update_at_a_named_point_and_bad_requests(runtime: RobotRuntime) -> None:
    with pytest.raises(NotFound):
        runtime.start_mapping("no_such_map")
    with pytest.raises(NotFound):
        runtime.start_mapping("partial", point="no_such_point")
    with pytest.raises(InvalidRequest):
        runtime.start_mapping(point="lobby")  # a point without a map
    with pytest.raises(InvalidRequest):
        runtime.start_mapping("partial", point="lobby", pose=Pose2D(1.0, 1.0, 0.0))
    assert runtime.mode is Mode.FREE
    runtime.start_mapping("floor1", point="lobby")  # the robot is carried there
    runtime.advance(0.5)
    lobby = Pose2D(5.5, 12.5, 0.0)
    assert runtime.simulation.true_pose.distance_to(lobby) < 0.05
    assert runtime.status().pose.distance_to(lobby) < 0.1
    runtime.cancel_mapping()
