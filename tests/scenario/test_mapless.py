"""Navigation without a prior map, on simulated time: the stack never sees the world's map.

The lidar builds a rolling costmap, scan matching against the robot's own scans keeps the pose
in the odometry frame, and a goal "10 m ahead" through a field of posts is reached.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.geometry import Pose2D
from polynav.maps.map import Map, MapInfo
from polynav.nav import events
from polynav.nav.attempt import NavigationState
from polynav.nav.mapless import MaplessConfig, MaplessStack
from polynav.robot.profile import load_profile
from polynav.runtime.sim_driver import SimDriver, simulate_mapless
from polynav.site import Point, PointKind
from polynav.worlds.world import World, WorldFloor

RESOLUTION = 0.05


def post_field(seed: int, *, width: float = 16.0, height: float = 8.0, spacing: float = 1.3,
               post: float = 0.1) -> World:
    """A walled box with square posts ``post`` m wide on a jittered grid ``spacing`` apart,
    leaving the start and goal areas clear; the gaps stay wider than the robot by
    construction (spacing - post - 2 x jitter)."""
    rng = np.random.default_rng(seed)
    w, h = int(round(width / RESOLUTION)), int(round(height / RESOLUTION))
    data = np.zeros((h, w), dtype=np.int8)
    data[0, :] = data[-1, :] = data[:, 0] = data[:, -1] = 100
    jitter = 0.15
    cells = int(round(post / RESOLUTION))
    for px in np.arange(3.5, width - 2.5, spacing):
        for py in np.arange(1.0, height - 0.5, spacing):
            x = px + rng.uniform(-jitter, jitter)
            y = py + rng.uniform(-jitter, jitter)
            ix, iy = int(x / RESOLUTION), int(y / RESOLUTION)
            data[iy:iy + cells, ix:ix + cells] = 100
    grid = Map(MapInfo(RESOLUTION, w, h, Pose2D()), data)
    start = Pose2D(1.5, height / 2, 0.0)
    floor = WorldFloor(name="field", level=0, map_name="field", map=grid,
                       points=(Point("start", "field", start, PointKind.INITIAL),), lift=None,
                       people=())
    return World(name="posts", floors=(floor,), start_floor="field", start_pose=start)


def _run(driver: SimDriver, goal: Pose2D, timeout: float) -> NavigationState:
    driver.stack.go_to(goal, driver.now)
    driver.run_until(lambda: driver.stack.navigator.state.finished, timeout)
    return driver.stack.navigator.state


@pytest.mark.parametrize("seed", [1, 2])
def test_a_mapless_goal_10m_ahead_through_posts_is_reached(seed: int) -> None:
    world = post_field(seed)
    seen: list[object] = []
    driver = simulate_mapless(world, seed=seed, people=False, on_event=seen.append)
    assert isinstance(driver.stack, MaplessStack)
    start = driver.sim.true_pose
    assert driver.sim.odometry.pose == Pose2D()  # the odometry frame starts where it stands
    # "10 m ahead" is the pose (10, 0, 0) in the odometry frame, wherever the robot stands.
    assert _run(driver, Pose2D(10.0, 0.0, 0.0), timeout=90.0) is NavigationState.SUCCEEDED
    true = driver.sim.true_pose
    goal = start.compose(Pose2D(10.0, 0.0, 0.0))
    assert true.distance_to(goal) <= 0.25, true  # odometry-frame drift over 10 m included
    assert driver.sim.collisions == []
    # The same events as with a map.
    kinds = {type(e) for e in seen}
    assert events.NavigationStarted in kinds and events.NavigationSucceeded in kinds


def test_mapless_stack_never_saw_the_map_and_marks_the_posts() -> None:
    world = post_field(3)
    driver = simulate_mapless(world, seed=3, people=False)
    driver.run(1.0)
    stack = driver.stack
    assert stack.map is not world.floors[0].map
    cm = stack.costmap
    # A post 2 m ahead is marked; far space behind posts is still unknown.
    assert np.count_nonzero(cm.costs == 254) > 10
    assert np.count_nonzero(cm.costs == 255) > 0


def test_window_rolls_with_the_robot_and_holds_a_far_goal() -> None:
    world = post_field(4, width=40.0, height=8.0)
    driver = simulate_mapless(world, seed=4, people=False,
                              mapless=MaplessConfig(window=16.0, edge_margin=4.0))
    goal = Pose2D(36.0, 4.0, 0.0)  # in the world: 34.5 m ahead of the start
    state = _run(driver, driver.to_odometry(goal), timeout=150.0)
    assert state is NavigationState.SUCCEEDED
    assert driver.sim.collisions == []
    stack = driver.stack
    assert isinstance(stack, MaplessStack) and stack.recentred >= 1
    assert driver.sim.true_pose.distance_to(goal) <= 0.5


def test_research_base_mapless_through_posts() -> None:
    world = post_field(5, spacing=1.5)
    driver = simulate_mapless(world, seed=5, people=False,
                              profile=load_profile("research-base"))
    goal = driver.sim.true_pose.compose(Pose2D(10.0, 0.0, 0.0))
    assert _run(driver, Pose2D(10.0, 0.0, 0.0), timeout=60.0) is NavigationState.SUCCEEDED
    assert driver.sim.true_pose.distance_to(goal) <= 0.25
    assert driver.sim.collisions == []
    assert math.isfinite(driver.stack.estimate.quality)
