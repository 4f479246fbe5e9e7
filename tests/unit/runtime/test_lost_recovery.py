"""A lost robot finds itself: the global search on request, and by itself while LOST, so that a
robot carried away mid-goal (kidnapped) recovers and completes its goal."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from polynav.errors import Conflict, NotLocalized
from polynav.geometry import Pose2D
from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds import load_world

WORLD = load_world("demo")


@pytest.fixture
def runtime(tmp_path: Path) -> Iterator[RobotRuntime]:
    with SiteStore.open(tmp_path / "data", seed_world=WORLD) as store:
        yield RobotRuntime.simulated(store, WORLD, config=RuntimeConfig(people=False, seed=2))


def _kinds(events: list) -> list[str]:
    return [e.kind for e in events]


def test_a_kidnapped_robot_relocalizes_by_itself_and_completes_its_goal(
    runtime: RobotRuntime,
) -> None:
    runtime.start_navigation("floor1")
    runtime.advance(1.0)
    sub = runtime.bus.subscribe()
    goal = WORLD.floor("floor1").point("kitchen").pose
    runtime.go_to(point="kitchen")
    runtime.advance(4.0)
    # Carried away to the lobby's far side, turned round: the tracker's pose is now wrong.
    runtime.simulation.teleport("floor1", Pose2D(3.0, 6.0, 2.5))
    done = runtime.advance_until(lambda: runtime.status().navigation_state != "running", 240.0)
    assert done and runtime.status().navigation_state == "succeeded", runtime.status()
    seen = sub.get_nowait()
    lost = next(k for k, e in enumerate(seen)
                if e.kind == "localization_changed" and e.state == "lost")  # type: ignore[attr-defined]
    assert "pose_initialized" in _kinds(seen[lost:])  # found by the global search, not by hand
    assert runtime.simulation.true_pose.distance_to(goal) <= 0.15
    assert runtime.status().localization_state == "tracking"


def test_relocalize_on_request_restarts_localization_at_the_true_pose(
    runtime: RobotRuntime,
) -> None:
    with pytest.raises(Conflict):
        runtime.relocalize()  # not navigating
    runtime.start_navigation("floor1")
    runtime.advance(1.0)
    runtime.simulation.teleport("floor1", Pose2D(24.0, 12.0, -1.0))
    runtime.advance(0.2)
    result = runtime.relocalize()
    assert result.pose is not None and result.score > 0.5
    assert result.pose.distance_to(runtime.simulation.true_pose) <= 0.1
    runtime.advance(1.0)
    assert runtime.status().pose.distance_to(runtime.simulation.true_pose) <= 0.1


def test_relocalize_in_a_place_that_matches_nowhere_is_refused(
    runtime: RobotRuntime,
) -> None:
    runtime.start_navigation("floor1")
    runtime.advance(0.5)
    # The robot is taken to floor 2 but navigates on floor 1's map: its scan fits nowhere.
    runtime.simulation.teleport("floor2", Pose2D(5.0, 12.0, 0.0))
    runtime.advance(0.2)
    with pytest.raises(NotLocalized):
        runtime.relocalize()
