"""Mapping mode end to end on the simulator: start where the robot stands, drive it by teleop,
watch the map grow, save it (409 on a taken name unless overwrite), stop (saves, FREE), cancel;
then navigate on the new map."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

from polynav.errors import Conflict
from polynav.geometry import Pose2D
from polynav.runtime.config import Mode, RuntimeConfig
from polynav.runtime.robot_runtime import RobotRuntime
from polynav.store.site_store import SiteStore
from polynav.worlds import load_world

WORLD = load_world("demo")


@pytest.fixture
def runtime(tmp_path: Path) -> Iterator[RobotRuntime]:
    with SiteStore.open(tmp_path / "data", seed_world=WORLD) as store:
        yield RobotRuntime.simulated(store, WORLD, config=RuntimeConfig(people=False, seed=4))


def _drive(runtime: RobotRuntime, linear: float, angular: float, seconds: float) -> None:
    for _ in range(round(seconds / 0.2)):
        runtime.teleop(linear, angular)
        runtime.advance(0.2)


def test_a_map_is_built_while_driving_saved_and_navigated_on(runtime: RobotRuntime) -> None:
    with pytest.raises(Conflict):
        runtime.stop_mapping("new")  # not mapping
    runtime.start_mapping()
    assert runtime.mode is Mode.MAPPING
    empty = runtime.mapping_map()  # nothing scanned yet: one unknown cell, still a map
    assert (empty.info.width, empty.info.height, int(empty.data[0, 0])) == (1, 1, -1)
    with pytest.raises(Conflict):
        runtime.start_navigation("floor1")
    with pytest.raises(Conflict):
        runtime.start_mapping()
    runtime.advance(0.5)
    first = runtime.mapping_map()
    _drive(runtime, 0.5, 0.0, 6.0)  # along the lobby
    _drive(runtime, 0.0, 0.8, 2.0)
    _drive(runtime, 0.4, 0.0, 3.0)
    grown = runtime.mapping_map()
    known = lambda grid: int(np.count_nonzero(grid.data >= 0))  # noqa: E731
    assert known(grown) > known(first) > 0
    # The status follows the robot on the new map, which shares the world's frame here.
    status = runtime.status()
    assert status.mode == "mapping"
    assert status.pose.distance_to(runtime.simulation.true_pose) < 0.3
    runtime.save_mapping("lobby_draft")
    with pytest.raises(Conflict, match="exists"):
        runtime.save_mapping("lobby_draft")
    runtime.save_mapping("lobby_draft", overwrite=True)
    with pytest.raises(Conflict, match="exists"):
        runtime.stop_mapping("floor1")  # the demo's own map
    assert runtime.mode is Mode.MAPPING  # a refused stop changes nothing
    record = runtime.stop_mapping("lobby")
    assert runtime.mode is Mode.FREE
    assert record.floor == "floor1"
    # Navigate on the new map, to a place the robot mapped.
    runtime.start_navigation("lobby")
    runtime.advance(1.0)
    assert runtime.status().localization_state == "tracking"
    target = runtime.simulation.true_pose
    runtime.go_to(pose=target.compose(Pose2D(-1.5, 0.0, 0.0)))
    assert runtime.advance_until(lambda: runtime.status().navigation_state != "running", 60.0)
    assert runtime.status().navigation_state == "succeeded"


def test_cancel_drops_the_map(runtime: RobotRuntime) -> None:
    with pytest.raises(Conflict):
        runtime.cancel_mapping()
    runtime.start_mapping()
    runtime.advance(0.5)
    runtime.cancel_mapping()
    assert runtime.mode is Mode.FREE
    with pytest.raises(Conflict):
        runtime.mapping_map()
    assert "lobby" not in [record.name for record in runtime.store.maps()]  # type: ignore[attr-defined]


def test_mapping_starts_from_free_only(runtime: RobotRuntime) -> None:
    runtime.start_navigation("floor1")
    runtime.advance(0.5)
    with pytest.raises(Conflict, match="stop navigation first"):
        runtime.start_mapping()
