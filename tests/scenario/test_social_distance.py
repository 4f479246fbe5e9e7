"""The social distance, on simulated time with the whole stack: a robot crossing a room keeps
it from a person standing in its way and from a slow walker it follows down a corridor, and the
distance it closes in to is measured on the ground truth while the robot itself moves towards
them.

The world: one 10 m x 6 m room with a few pieces of furniture (for localization), the robot on
the west side, its goal on the east side; and a corridor too narrow to pass anyone in.
"""

from __future__ import annotations

import math

import numpy as np

from polynav.geometry import Pose2D
from polynav.maps.map import Map, MapInfo
from polynav.nav.attempt import NavigationState
from polynav.nav.people import PeopleConfig
from polynav.nav.stack import StackConfig
from polynav.runtime.sim_driver import SimDriver, simulate
from polynav.worlds.world import PersonRoute, World, WorldFloor

RES = 0.05
START = Pose2D(1.5, 3.0, 0.0)
GOAL = Pose2D(8.5, 3.0, 0.0)
SOCIAL = PeopleConfig().social_distance


def _room(person: PersonRoute) -> World:
    width, height = int(10.0 / RES), int(6.0 / RES)
    data = np.zeros((height, width), dtype=np.int8)
    wall = 4
    data[:wall, :] = data[-wall:, :] = 100
    data[:, :wall] = data[:, -wall:] = 100
    for x, y in ((1.0, 1.0), (4.0, 5.2), (7.0, 0.8), (9.2, 4.8)):
        ix, iy = int(x / RES), int(y / RES)
        data[iy - 5: iy + 5, ix - 5: ix + 5] = 100
    grid = Map(MapInfo(RES, width, height, Pose2D(0.0, 0.0, 0.0)), data)
    return World("room", (WorldFloor("f", 1, "f", grid, (), None, (person,)),), "f", START)


def _cross(
    person: PersonRoute, *, world: World | None = None, goal: Pose2D = GOAL
) -> tuple[SimDriver, float, float]:
    """Drive to the goal; the closest approach overall, and while the robot closed in."""
    driver = simulate(world or _room(person), seed=5, stack_config=StackConfig())
    driver.stack.go_to(goal, driver.now)
    closest = approached = math.inf
    last: float | None = None
    end = driver.now + 120.0
    while not driver.stack.navigator.state.finished and driver.now < end:
        driver.step()
        true, speed = driver.sim.true_pose, driver.sim.true_twist.linear
        (p,) = driver.sim.people_poses()
        dx, dy = p.x - true.x, p.y - true.y
        d = math.hypot(dx, dy)
        closest = min(closest, d)
        towards = speed * (dx * math.cos(true.theta) + dy * math.sin(true.theta)) / d
        if last is not None and d < last and towards > 0.02:
            approached = min(approached, d)
        last = d
    return driver, closest, approached


def test_goes_round_a_person_standing_in_the_way_at_the_social_distance() -> None:
    person = PersonRoute(((5.0, 3.0), (5.0, 3.0)), speed=0.8)  # stands on the straight line
    driver, closest, approached = _cross(person)
    assert driver.stack.navigator.state is NavigationState.SUCCEEDED
    assert driver.sim.true_pose.distance_to(GOAL) <= 0.15
    assert closest >= SOCIAL - 0.01 and approached >= SOCIAL - 0.01, (closest, approached)
    assert driver.sim.collisions == []


def _corridor(person: PersonRoute) -> World:
    width, height = int(14.0 / RES), int(1.8 / RES)
    data = np.zeros((height, width), dtype=np.int8)
    data[:4, :] = data[-4:, :] = 100
    data[:, :4] = data[:, -4:] = 100
    for x in (2.0, 5.0, 8.0, 11.0):  # alcoves' posts, so the scan pins the pose along it
        ix = int(x / RES)
        data[4:7, ix: ix + 4] = 100
    grid = Map(MapInfo(RES, width, height, Pose2D(0.0, 0.0, 0.0)), data)
    start = Pose2D(1.0, 0.9, 0.0)
    return World("corridor", (WorldFloor("f", 1, "f", grid, (), None, (person,)),), "f", start)


def test_follows_a_slow_walker_down_a_corridor_at_the_social_distance() -> None:
    # No room to pass: the robot comes up behind and keeps its distance at their pace.
    person = PersonRoute(((2.6, 0.9), (13.5, 0.9)), speed=0.2, loop=False)
    driver, closest, approached = _cross(person, world=_corridor(person),
                                         goal=Pose2D(11.0, 0.9, 0.0))
    assert driver.stack.navigator.state is NavigationState.SUCCEEDED
    assert approached >= SOCIAL - 0.01, (closest, approached)
    assert driver.sim.collisions == []
