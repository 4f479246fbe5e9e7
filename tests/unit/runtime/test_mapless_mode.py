"""The runtime's mapless mode: NAVIGATING with no map, goals as odometry-frame poses through the
same goal command, the same events and status as on a map."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from polynav.errors import Conflict, InvalidRequest, NotFound
from polynav.geometry import Pose2D
from polynav.runtime import events
from polynav.runtime.config import Mode, RuntimeConfig
from polynav.runtime.goal_commands import GoalFrame
from polynav.runtime.mapless_commands import MAPLESS_FRAME
from polynav.runtime.robot_runtime import RobotRuntime
from polynav.store.site_store import SiteStore
from tests.scenario.test_mapless import post_field


@pytest.fixture
def runtime(tmp_path: Path) -> Iterator[RobotRuntime]:
    world = post_field(7)
    with SiteStore.open(tmp_path / "data", seed_world=world) as store:
        yield RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False, seed=7))


def test_mapless_goal_through_the_runtime_is_reached_with_the_usual_events(
    runtime: RobotRuntime,
) -> None:
    sub = runtime.bus.subscribe()
    runtime.start_mapless()
    assert runtime.mode is Mode.NAVIGATING and runtime.mapless
    assert runtime.map_name == MAPLESS_FRAME
    start = runtime.simulation.true_pose
    goal = start.compose(Pose2D(10.0, 0.0, 0.0))
    attempt = runtime.go_to(pose=Pose2D(10.0, 0.0, 0.0))  # odometry frame: 10 m ahead
    assert runtime.advance_until(lambda: runtime.status().navigation_state == "succeeded",
                                 timeout=90.0)
    assert runtime.simulation.true_pose.distance_to(goal) <= 0.25
    assert runtime.simulation.collisions == []
    seen: list[events.RuntimeEvent] = sub.get_nowait()
    names = [type(e).__name__ for e in seen]
    assert "NavigationStarted" in names and "NavigationSucceeded" in names
    assert runtime.status().attempt_id == attempt
    runtime.stop_navigation()
    assert runtime.mode is Mode.FREE and not runtime.mapless


def test_mapless_refuses_points_and_initial_poses_and_mapping(runtime: RobotRuntime) -> None:
    runtime.start_mapless()
    with pytest.raises(NotFound):
        runtime.go_to(point="start")
    with pytest.raises(Conflict, match="odometry"):
        runtime.set_initial_pose(Pose2D(1.0, 1.0, 0.0))
    with pytest.raises(Conflict):
        runtime.start_mapping()
    runtime.stop_navigation()
    runtime.start_mapping()
    with pytest.raises(Conflict, match="mapping"):
        runtime.start_mapless()


def test_status_names_the_odometry_frame_and_a_robot_frame_goal_is_turned_into_it(
    runtime: RobotRuntime,
) -> None:
    assert runtime.status().frame == "map"  # free: the simulator's pose on the floor's map
    runtime.start_mapless()
    runtime.advance(0.5)
    status = runtime.status()
    assert status.frame == "odom" and status.pose.distance_to(Pose2D()) < 0.05
    runtime.go_to(pose=Pose2D(2.0, 1.0, 0.5), frame=GoalFrame.ROBOT)
    goal, expected = runtime.status().goal, status.pose.compose(Pose2D(2.0, 1.0, 0.5))
    assert goal is not None
    assert (goal.x, goal.y, goal.theta) == pytest.approx((expected.x, expected.y, expected.theta))
    runtime.go_to(pose=Pose2D(1.0, 0.0, 0.0), frame=GoalFrame.ODOM)
    with pytest.raises(Conflict, match="no map frame"):
        runtime.go_to(pose=Pose2D(1.0, 0.0, 0.0), frame=GoalFrame.MAP)
    with pytest.raises(InvalidRequest):
        runtime.go_to(point="start", frame=GoalFrame.ROBOT)
    runtime.stop_navigation()
    assert runtime.status().frame == "map"
