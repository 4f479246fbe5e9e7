"""Whole missions on the demo site, on simulated time, deterministic for a seed.

Each test drives the full stack: simulated lidar/odometry/IMU, localization on those noisy
sensors, the layered costmap, the planner and the controller. Ground truth is used only to judge.
"""

from __future__ import annotations

import math

import pytest

from polynav.geometry import Pose2D
from polynav.localization.interface import LocalizationState
from polynav.maps.keepout import VirtualWall
from polynav.nav import events
from polynav.nav.attempt import FailureReason, GoalOptions, NavigationState
from polynav.runtime.sim_driver import SimDriver, simulate
from polynav.site import PointKind
from polynav.worlds.world import World

POSITION_TOLERANCE = 0.1
HEADING_TOLERANCE = 0.1


def _finished(driver: SimDriver) -> bool:
    return driver.stack.navigator.state.finished


def _assert_at(driver: SimDriver, goal: Pose2D) -> None:
    true = driver.sim.true_pose
    assert true.distance_to(goal) <= POSITION_TOLERANCE, (true, goal)
    assert abs(true.heading_error_to(goal)) <= HEADING_TOLERANCE, (true, goal)


def test_reaches_every_named_point_of_floor_one(world: World) -> None:
    floor = world.floor(world.start_floor)
    driver = simulate(world, seed=1, people=False)
    reached = []
    for point in floor.points:
        # A charger point is the docked pose, its plate touching the body: it is docked onto.
        docking = GoalOptions(dock=True) if point.kind is PointKind.CHARGER else None
        driver.stack.go_to(point.pose, driver.now, docking)
        assert driver.run_until(lambda: _finished(driver), timeout=180.0), point.name
        attempt = driver.stack.navigator.attempt
        assert attempt is not None
        assert attempt.state is NavigationState.SUCCEEDED, (point.name, attempt)
        _assert_at(driver, point.pose)
        reached.append(point.name)
    assert reached == [p.name for p in floor.points]
    assert driver.sim.collisions == []


def test_reaches_a_goal_while_people_cross_the_corridor(world: World) -> None:
    floor = world.floor(world.start_floor)
    assert floor.people, "the demo floor has walkers"
    log: list[events.NavigationEvent] = []
    driver = simulate(world, seed=2, people=True, on_event=log.append)
    # The point farthest from the start makes the robot cross the walkers' corridor.
    goal = max(floor.points, key=lambda p: p.pose.distance_to(world.start_pose)).pose
    driver.stack.go_to(goal, driver.now)
    assert driver.run_until(lambda: _finished(driver), timeout=240.0)
    assert driver.stack.navigator.state is NavigationState.SUCCEEDED
    _assert_at(driver, goal)
    assert driver.sim.collisions == []
    assert isinstance(log[0], events.NavigationStarted)
    assert isinstance(log[-1], events.NavigationSucceeded)


def _boxed_in_goal(world: World) -> Pose2D:
    floor = world.floor(world.start_floor)
    return next(p for p in floor.points if p.kind is PointKind.GENERAL).pose


def test_unreachable_goal_fails_with_no_path_within_seconds(world: World) -> None:
    driver = simulate(world, seed=3, people=False)
    goal = _boxed_in_goal(world)
    h = 0.6
    corners = ((goal.x - h, goal.y - h), (goal.x + h, goal.y - h), (goal.x + h, goal.y + h),
               (goal.x - h, goal.y + h), (goal.x - h, goal.y - h))
    driver.stack.costmap.set_keepouts([VirtualWall(points=corners, thickness=0.1)])
    start = driver.sim.true_pose
    started_at = driver.now
    driver.stack.go_to(goal, driver.now)
    assert driver.run_until(lambda: _finished(driver), timeout=5.0)
    attempt = driver.stack.navigator.attempt
    assert attempt is not None
    assert attempt.state is NavigationState.FAILED
    assert attempt.reason is FailureReason.NO_PATH
    assert attempt.ended_at is not None and attempt.ended_at - started_at < 1.0
    assert driver.sim.true_pose.distance_to(start) < 0.05


def test_goal_inside_a_wall_fails_with_goal_occupied(world: World) -> None:
    floor = world.floor(world.start_floor)
    occupied = floor.map.occupied()
    iy, ix = (int(v[0]) for v in occupied.nonzero())
    x, y = floor.map.info.cell_to_world(ix, iy)
    driver = simulate(world, seed=4, people=False)
    driver.stack.go_to(Pose2D(x, y, 0.0), driver.now)
    assert driver.run_until(lambda: _finished(driver), timeout=5.0)
    attempt = driver.stack.navigator.attempt
    assert attempt is not None and attempt.reason is FailureReason.GOAL_OCCUPIED


def _far_point(world: World) -> Pose2D:
    floor = world.floor(world.start_floor)
    return max(floor.points, key=lambda p: p.pose.distance_to(world.start_pose)).pose


@pytest.mark.parametrize("button", ["hardware", "software"])
def test_estop_stops_within_one_control_period_and_resumes_only_when_released(
    world: World, button: str
) -> None:
    driver = simulate(world, seed=5, people=False)
    goal = _far_point(world)
    driver.stack.go_to(goal, driver.now)
    driver.run(6.0)
    assert driver.sim.true_twist.linear > 0.2
    if button == "hardware":
        driver.sim.press_estop()
    else:
        driver.stack.software_estop = True
    period = 1.0 / driver.stack.config.control_rate
    driver.run(period)
    assert driver.stack.command.linear == 0.0 and driver.stack.command.angular == 0.0
    # The base then brakes to a stand-still and stays there while the e-stop is held.
    driver.run(1.0)
    held_at = driver.sim.true_pose
    assert driver.sim.true_twist.linear == 0.0
    driver.run(10.0)
    assert driver.sim.true_pose.distance_to(held_at) < 1e-6
    assert driver.stack.navigator.state is NavigationState.RUNNING
    if button == "hardware":
        driver.sim.release_estop()
    else:
        driver.stack.software_estop = False
    assert driver.run_until(lambda: _finished(driver), timeout=180.0)
    assert driver.stack.navigator.state is NavigationState.SUCCEEDED
    _assert_at(driver, goal)


def test_cancel_stops_the_robot_and_ends_canceled(world: World) -> None:
    log: list[events.NavigationEvent] = []
    driver = simulate(world, seed=6, people=False, on_event=log.append)
    driver.stack.go_to(_far_point(world), driver.now)
    driver.run(5.0)
    assert driver.stack.navigator.cancel(driver.now)
    driver.run(2.0)
    assert driver.stack.navigator.state is NavigationState.CANCELED
    assert driver.sim.true_twist.linear == 0.0
    stopped_at = driver.sim.true_pose
    driver.run(5.0)
    assert driver.sim.true_pose.distance_to(stopped_at) < 1e-6
    assert isinstance(log[-1], events.NavigationCanceled)


def test_pause_holds_and_resume_reaches_the_goal(world: World) -> None:
    log: list[events.NavigationEvent] = []
    driver = simulate(world, seed=7, people=False, on_event=log.append)
    goal = _far_point(world)
    driver.stack.go_to(goal, driver.now)
    driver.run(5.0)
    assert driver.stack.navigator.pause(driver.now)
    driver.run(2.0)
    paused_at = driver.sim.true_pose
    driver.run(5.0)
    assert driver.stack.navigator.state is NavigationState.PAUSED
    assert driver.sim.true_pose.distance_to(paused_at) < 1e-6
    assert driver.stack.navigator.resume(driver.now)
    assert driver.run_until(lambda: _finished(driver), timeout=180.0)
    assert driver.stack.navigator.state is NavigationState.SUCCEEDED
    _assert_at(driver, goal)
    kinds = [type(e).__name__ for e in log]
    assert kinds.index("NavigationPaused") < kinds.index("NavigationResumed")
    assert kinds[-1] == "NavigationSucceeded"


def test_relocalization_from_half_a_metre_and_twenty_degrees_off_converges(
    world: World,
) -> None:
    true = world.start_pose
    guess = Pose2D(true.x + 0.35, true.y - 0.35, true.theta + math.radians(20))
    driver = simulate(world, seed=8, people=False, initial_guess=guess)
    driver.run(3.0)
    estimate = driver.stack.estimate
    assert estimate.state is LocalizationState.TRACKING
    assert estimate.pose.distance_to(driver.sim.true_pose) < 0.05
    assert abs(estimate.pose.heading_error_to(driver.sim.true_pose)) < math.radians(2)
