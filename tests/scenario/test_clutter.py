"""Clutter at close quarters, whole missions on simulated time (issue 18's acceptance tests).

Each test builds a small walled room with thin posts (disks of a few cells) on a 0.05 m grid and
drives the full stack on the simulator: ray-cast lidar with range noise, noisy odometry, the real
body (disk or polygon) colliding with the ground truth. Ground truth only judges.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.geometry import Pose2D
from polynav.maps.map import Map
from polynav.nav import events
from polynav.nav.attempt import NavigationState
from polynav.robot.profile import load_profile
from polynav.runtime.sim_driver import SimDriver, simulate
from polynav.worlds.world import World, WorldFloor

RES = 0.05  # [m]
POST = 0.06  # [m] post radius


def _room(length: float, width: float, posts: list[tuple[float, float]],
          walls: list[tuple[float, float, float, float]] = (), *,  # type: ignore[assignment]
          start: Pose2D) -> World:
    """A room ``length`` x ``width`` [m] inside 0.2 m walls (the inside starts at (0.2, 0.2)),
    with posts at the given centres and extra wall boxes (x0, y0, x1, y1)."""
    wall = 0.2
    nx, ny = round((length + 2 * wall) / RES), round((width + 2 * wall) / RES)
    w = round(wall / RES)
    occupied = np.ones((ny, nx), dtype=bool)
    occupied[w:ny - w, w:nx - w] = False
    iy, ix = np.mgrid[0:ny, 0:nx]
    cx, cy = (ix + 0.5) * RES, (iy + 0.5) * RES
    for px, py in posts:
        occupied |= np.hypot(cx - px, cy - py) <= POST
    for x0, y0, x1, y1 in walls:
        occupied |= (cx >= x0) & (cx <= x1) & (cy >= y0) & (cy <= y1)
    grid = Map.from_occupied(occupied, resolution=RES)
    floor = WorldFloor(name="floor1", level=1, map_name="room", map=grid, points=(), lift=None,
                       people=())
    return World(name="room", floors=(floor,), start_floor="floor1", start_pose=start)


def _go(driver: SimDriver, goal: Pose2D, timeout: float) -> list[events.NavigationEvent]:
    seen: list[events.NavigationEvent] = []
    driver.stack.navigator.subscribe(seen.append)
    driver.stack.go_to(goal, driver.now)
    assert driver.run_until(lambda: driver.stack.navigator.state.finished, timeout=timeout)
    return seen


@pytest.mark.parametrize("seed", [0, 1])
def test_a_robot_03_m_from_a_post_turns_in_place_without_a_block(seed: int) -> None:
    # The demo robot (a 0.25 m disk) faces a post whose surface is 0.30 m ahead of its centre,
    # and its goal is behind it: it must turn round on the spot, 5 cm from the post, while its
    # odometry reports a few mm/s of noise.
    start = Pose2D(3.2, 2.2, 0.0)
    world = _room(6.0, 4.0, [(start.x + 0.30 + POST, start.y)], start=start)
    driver = simulate(world, seed=seed, people=False)
    driver.run(1.0)
    seen = _go(driver, Pose2D(1.2, 2.2, math.pi), timeout=40.0)
    assert driver.stack.navigator.state is NavigationState.SUCCEEDED
    assert not [e for e in seen if isinstance(e, events.NavigationBlocked)]
    assert not [e for e in seen if isinstance(e, events.NavigationRetry)]
    assert driver.sim.collisions == []


def test_a_rectangular_robot_wedged_between_posts_backs_out_through_the_ladder() -> None:
    # A 0.51 x 0.43 m base with posts 5 cm off both long sides and one 5 cm off its nose: its
    # corners (0.33 m out) cannot swing round either way, and the goal is behind it. Turning is
    # refused (blocked), the ladder clears, then backs up out of the wedge, and then it turns.
    profile = load_profile("research-base")
    hx, hy = 0.255, 0.215
    start = Pose2D(3.2, 2.2, 0.0)
    posts = [
        (start.x, start.y + hy + 0.05 + POST),
        (start.x, start.y - hy - 0.05 - POST),
        (start.x + hx + 0.05 + POST, start.y),
    ]
    world = _room(6.0, 4.0, posts, start=start)
    driver = simulate(world, seed=2, people=False, profile=profile)
    driver.run(1.0)
    seen = _go(driver, Pose2D(1.2, 2.2, math.pi), timeout=90.0)
    assert driver.stack.navigator.state is NavigationState.SUCCEEDED
    recoveries = [e.recovery for e in seen if isinstance(e, events.NavigationRetry)]
    assert any("back up" in r for r in recoveries), recoveries
    assert driver.sim.collisions == []
    assert driver.sim.true_pose.distance_to(Pose2D(1.2, 2.2)) < 0.15


def test_a_polygon_footprint_that_fits_a_gap_only_lengthwise_passes_it() -> None:
    # A wall across the room with one 0.60 m gap: wider than the base (0.43 m) but narrower than
    # its circumscribed circle (0.67 m). It gets through only heading along the gap.
    profile = load_profile("research-base")
    fp = profile.footprint
    gap = 0.60
    assert 2 * fp.inscribed_radius < gap < 2 * fp.circumscribed_radius
    start = Pose2D(1.5, 2.2, 0.0)
    wall_x0, wall_x1 = 3.2, 3.3
    gy0, gy1 = 2.2 - gap / 2, 2.2 + gap / 2
    walls = [(wall_x0, 0.0, wall_x1, gy0), (wall_x0, gy1, wall_x1, 10.0)]
    world = _room(6.0, 4.0, [], walls, start=start)
    driver = simulate(world, seed=4, people=False, profile=profile)
    driver.run(1.0)
    goal = Pose2D(5.0, 2.2, 0.0)
    _go(driver, goal, timeout=60.0)
    assert driver.stack.navigator.state is NavigationState.SUCCEEDED
    assert driver.sim.collisions == []
    assert driver.sim.true_pose.distance_to(goal) < 0.15
