"""Degenerate geometry, whole missions: a 100 m corridor and a warehouse of 1 m aisles.

A scan in a corridor pins the robot across it and in heading, never along it; in the middle of
an open hall it pins nothing at all. The tracker must then drive on odometry and IMU and stay
TRACKING (issue 10), and take the scan's word again as soon as the walls say something. Each
test runs the full stack on the simulator (ray-cast lidar, noisy odometry, gyro with a bias) on
simulated time; ground truth only judges.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.typing import NDArray

from polynav.geometry import Pose2D
from polynav.localization.interface import LocalizationState
from polynav.maps import movingai
from polynav.maps.map import Map
from polynav.nav.attempt import NavigationState
from polynav.runtime.sim_driver import SimDriver, simulate
from polynav.worlds.world import World, WorldFloor
from tests.conftest import DATA

RES = 0.05  # [m] per pixel of the worlds built here


def _world(occupied: NDArray[np.bool_], start: Pose2D, name: str) -> World:
    grid = Map.from_occupied(occupied, resolution=RES)
    floor = WorldFloor(name="floor1", level=1, map_name=name, map=grid, points=(), lift=None,
                       people=())
    return World(name=name, floors=(floor,), start_floor="floor1", start_pose=start)


class Watch:
    """Called at every step of a run: records the worst localization error and every state."""

    def __init__(self, driver: SimDriver) -> None:
        self.driver = driver
        self.states: set[LocalizationState] = set()
        self.worst_error = 0.0
        self.lowest_quality = 1.0

    def __call__(self) -> bool:
        estimate = self.driver.stack.estimate
        self.states.add(estimate.state)
        if estimate.state is LocalizationState.TRACKING:
            self.worst_error = max(self.worst_error,
                                   estimate.pose.distance_to(self.driver.sim.true_pose))
            self.lowest_quality = min(self.lowest_quality, estimate.quality)
        return self.driver.stack.navigator.state.finished


# -- a 100 m x 1 m corridor ------------------------------------------------------------------

WALL = 0.2  # [m]


def _corridor(length: float = 100.0, width: float = 1.0) -> World:
    w, n, m = round(WALL / RES), round(length / RES), round(width / RES)
    occupied = np.ones((m + 2 * w, n + 2 * w), dtype=bool)
    occupied[w:w + m, w:w + n] = False
    return _world(occupied, Pose2D(WALL + 0.6, WALL + 0.5 * width, 0.0), "corridor")


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 1])
def test_driven_end_to_end_along_a_100_m_corridor_it_stays_tracking_and_arrives(seed):
    world = _corridor()
    driver = simulate(world, seed=seed, people=False)
    goal = Pose2D(WALL + 99.4, WALL + 0.5, 0.0)
    watch = Watch(driver)

    driver.stack.go_to(goal, driver.now)
    assert driver.run_until(watch, timeout=300.0)

    assert driver.stack.navigator.state is NavigationState.SUCCEEDED
    assert LocalizationState.LOST not in watch.states
    # Along the corridor odometry carries the pose for most of the 100 m; the far wall comes
    # into view and fixes it before the end.
    final = driver.stack.estimate.pose.distance_to(driver.sim.true_pose)
    assert final < 0.1, final
    assert driver.sim.true_pose.distance_to(goal) < 0.1
    assert watch.worst_error < 0.15, watch.worst_error
    # The scan fits across the corridor all the way: the quality says so.
    assert watch.lowest_quality > 0.9
    assert driver.sim.collisions == []


# -- a warehouse of parallel 1 m aisles --------------------------------------------------------

WAREHOUSE = DATA / "movingai" / "warehouse-20-40-10-2-1.map"
CELL = 1.0  # [m] per MovingAI cell
ROWS, COLS = 49, 86  # the map's corner: a 50 m open hall and three blocks of shelves


def _warehouse() -> tuple[World, NDArray[np.bool_]]:
    """The corner of a MovingAI warehouse at 1 m per cell, closed by a wall where it is cut.

    Shelves 10 m x 2 m stand in rows with 1 m aisles between them, beside a 50 m open hall
    whose middle is farther than the lidar's 12 m from anything.
    """
    blocked = movingai.load_grid(WAREHOUSE)[:ROWS, :COLS].copy()
    blocked[0, :] = blocked[-1, :] = blocked[:, 0] = blocked[:, -1] = True
    cells = blocked[::-1]  # row 0 of the file is the top: iy = H - 1 - row
    k = round(CELL / RES)
    occupied = np.kron(cells, np.ones((k, k), dtype=bool)).astype(bool)
    start = Pose2D(60.5, 47.5, 0.0)  # in the top aisle, beside the shelves
    assert not cells[47, 60]
    return _world(occupied, start, "warehouse"), ~cells


def _goals(free: NDArray[np.bool_], count: int, seed: int) -> list[Pose2D]:
    rng = np.random.default_rng(seed)
    iy, ix = np.nonzero(free)
    picks = rng.choice(len(iy), size=count, replace=False)
    return [Pose2D((ix[i] + 0.5) * CELL, (iy[i] + 0.5) * CELL,
                   float(rng.uniform(-math.pi, math.pi))) for i in picks]


@pytest.mark.slow
def test_twenty_random_goals_in_a_warehouse_of_1_m_aisles_are_all_reached():
    world, free = _warehouse()
    driver = simulate(world, seed=3, people=False)
    goals = _goals(free, 20, seed=3)
    reached, misses = [], []
    watch = Watch(driver)
    for goal in goals:
        driver.stack.go_to(goal, driver.now)
        assert driver.run_until(watch, timeout=400.0), goal
        miss = driver.sim.true_pose.distance_to(goal)
        misses.append(miss)
        if driver.stack.navigator.state is NavigationState.SUCCEEDED:
            reached.append(goal)
    assert len(reached) == len(goals), (len(reached), goals)
    assert LocalizationState.LOST not in watch.states
    assert driver.sim.collisions == []
    # In the middle of the hall no wall is in range and odometry alone has carried the robot
    # tens of metres; everywhere else the walls fix the pose to centimetres.
    assert max(misses) < 0.3, misses
    assert float(np.median(misses)) < 0.05, misses
