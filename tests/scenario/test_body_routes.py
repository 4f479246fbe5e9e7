"""Routes the body can drive, and traps remembered (issue 31's acceptance, on simulated time).

The rectangular ``research-base`` (0.51 x 0.43 m, diagonal 0.67 m, 2 m/s) in small rooms on a
0.05 m grid, the full stack on the simulator; ground truth only judges. Each case failed on the
code before: the planner inflating by the inscribed radius routed into a gap the body could not
turn into, and every retry planned the same gap again.
"""

from __future__ import annotations

import dataclasses
import math

import pytest

from polynav.geometry import Pose2D
from polynav.nav.attempt import FailureReason, NavigationState
from polynav.robot.profile import Reverse, RobotProfile, load_profile
from tests.helpers.rooms import drive, go, retries, room


@pytest.fixture(scope="module")
def base() -> RobotProfile:
    return load_profile("research-base")


# A 0.6 m gap (wider than the body, narrower than its diagonal) in a wall across the room, its
# only approach a 0.55 m channel along the wall: the body cannot turn from the channel into it.
_GAP_WALL = [(4.0, 0.2, 4.1, 2.15), (3.4, 1.9, 3.45, 3.0)]


def test_a_gap_the_rectangle_cannot_turn_into_is_gone_round(base: RobotProfile) -> None:
    # The wall ends 0.8 m short of the far side: the way round is 5 m longer than the gap's.
    world = room(8.0, 8.0, [*_GAP_WALL, (4.0, 2.75, 4.1, 7.2)])
    driver, seen = drive(world, Pose2D(1.5, 2.45, 0.0), base)
    goal = Pose2D(6.5, 2.45, 0.0)
    go(driver, goal, timeout=60.0)
    assert driver.stack.navigator.state is NavigationState.SUCCEEDED
    assert retries(seen) == []
    assert driver.sim.collisions == []
    assert driver.sim.true_pose.distance_to(goal) < 0.1
    # It went round the wall's end, never through the gap.
    assert driver.stack.navigator.attempt is not None
    assert driver.stack.navigator.attempt.distance_travelled > 9.0


def test_a_footprint_wider_than_every_way_fails_no_path_at_once(base: RobotProfile) -> None:
    world = room(8.0, 8.0, [*_GAP_WALL, (4.0, 2.75, 4.1, 8.2)])
    driver, seen = drive(world, Pose2D(1.5, 2.45, 0.0), base)
    began = driver.now
    go(driver, Pose2D(6.5, 2.45, 0.0), timeout=10.0)
    attempt = driver.stack.navigator.attempt
    assert attempt is not None and attempt.state is NavigationState.FAILED
    assert attempt.reason is FailureReason.NO_PATH
    assert driver.now - began < 2.0
    assert driver.sim.collisions == []


def test_a_post_the_map_does_not_have_closes_its_passage_and_the_robot_goes_round(
    base: RobotProfile,
) -> None:
    # Two ways through a wall; the map shows both open, but a post the map does not have
    # stands in the direct one (its two halves, 0.36 m each, are narrower than the body).
    walls = [(4.0, 0.2, 4.1, 0.3), (4.0, 1.2, 4.1, 2.0), (4.0, 2.9, 4.1, 4.6)]
    truth = room(8.0, 4.4, walls, posts=[(4.05, 2.45)], post_radius=0.03)
    driver, seen = drive(truth, Pose2D(1.5, 2.45, 0.0), base, seed=1, mapped=room(8.0, 4.4, walls))
    goal = Pose2D(6.5, 2.45, 0.0)
    go(driver, goal, timeout=60.0)
    assert driver.stack.navigator.state is NavigationState.SUCCEEDED
    assert driver.sim.collisions == []
    assert driver.sim.true_pose.distance_to(goal) < 0.1
    # Blocked once before the post at most; that passage is closed, never tried again.
    tried = retries(seen)
    assert len(tried) <= 1, tried
    assert all(cause.startswith("blocked at") for cause, _ in tried), tried


# A dead-end bay 0.6 m wide and 2.4 m deep, open towards the start.
_BAY = [(3.2, 2.1, 5.6, 2.15), (3.2, 2.75, 5.6, 2.8), (5.55, 2.1, 5.6, 2.8)]


def test_a_robot_in_a_pocket_it_cannot_turn_in_backs_out_and_goes_round(
    base: RobotProfile,
) -> None:
    # The robot is sent to the bay's far end, then to a goal behind it: it cannot turn in the
    # bay, so it backs out along the way it came in, turns at the mouth and drives on.
    driver, seen = drive(room(8.0, 4.4, _BAY), Pose2D(1.5, 2.45, 0.0), base)
    go(driver, Pose2D(5.0, 2.45, 0.0), timeout=30.0)
    assert driver.stack.navigator.state is NavigationState.SUCCEEDED
    seen.clear()
    began = driver.now
    goal = Pose2D(1.5, 1.0, math.pi)
    go(driver, goal, timeout=60.0)
    assert driver.stack.navigator.state is NavigationState.SUCCEEDED
    assert driver.sim.collisions == []
    assert driver.sim.true_pose.distance_to(goal) < 0.1
    recoveries = [recovery for _, recovery in retries(seen)]
    assert recoveries.count("back out") == 1, recoveries
    assert "clear around" not in recoveries  # no ladder of blind retries
    assert driver.now - began < 30.0


def test_a_robot_that_may_not_reverse_never_backs_out_of_the_pocket(base: RobotProfile) -> None:
    no_reverse = dataclasses.replace(base, reverse=Reverse(allowed=False))
    driver, seen = drive(room(8.0, 4.4, _BAY), Pose2D(1.5, 2.45, 0.0), no_reverse)
    go(driver, Pose2D(5.0, 2.45, 0.0), timeout=30.0)
    assert driver.stack.navigator.state is NavigationState.SUCCEEDED
    seen.clear()
    inside = driver.sim.true_pose
    go(driver, Pose2D(1.5, 1.0, math.pi), timeout=120.0)
    attempt = driver.stack.navigator.attempt
    assert attempt is not None and attempt.state is NavigationState.FAILED
    assert attempt.reason is FailureReason.STUCK
    recoveries = [recovery for _, recovery in retries(seen)]
    assert not [r for r in recoveries if "back" in r], recoveries
    assert driver.sim.true_pose.x > inside.x - 0.1  # it never drove backwards
    assert driver.sim.collisions == []
