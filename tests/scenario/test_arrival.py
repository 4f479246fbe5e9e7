"""How well the robot knows where it arrived (issue 31, item 5), whole missions on sim time.

A 40 m square hall: from its corners the lidar (12 m) sees two walls, from its middle none, so a
goal there is reached by dead reckoning. The arrival carries the localization's uncertainty, and
a goal that demands a precise arrival fails ``not localized`` rather than succeed off the point.
"""

from __future__ import annotations

import numpy as np
import pytest

from polynav.geometry import Pose2D
from polynav.maps.map import Map
from polynav.nav import events
from polynav.nav.attempt import FailureReason, GoalOptions, NavigationState
from polynav.runtime.sim_driver import SimDriver, simulate
from polynav.worlds.world import World, WorldFloor

RES = 0.1  # [m]: a coarse grid keeps a 40 m hall cheap; walls are all the matcher needs
SIDE = 40.0  # [m] inside
START = Pose2D(2.0, 2.0, 0.785)
MIDDLE = Pose2D(20.0, 20.0, 0.785)  # 20 m from every wall, beyond the lidar's 12 m


def _hall() -> World:
    wall = 0.3
    n = round((SIDE + 2 * wall) / RES)
    w = round(wall / RES)
    occupied = np.ones((n, n), dtype=bool)
    occupied[w:n - w, w:n - w] = False
    grid = Map.from_occupied(occupied, resolution=RES, origin=Pose2D(-wall, -wall, 0.0))
    floor = WorldFloor(name="floor1", level=1, map_name="hall", map=grid, points=(), lift=None,
                       people=())
    return World(name="hall", floors=(floor,), start_floor="floor1", start_pose=START)


def _go(driver: SimDriver, goal: Pose2D, options: GoalOptions | None = None
        ) -> list[events.NavigationEvent]:
    seen: list[events.NavigationEvent] = []
    driver.stack.navigator.subscribe(seen.append)
    driver.stack.go_to(goal, driver.now, options)
    assert driver.run_until(lambda: driver.stack.navigator.state.finished, timeout=180.0)
    return seen


@pytest.fixture(scope="module")
def hall() -> World:
    return _hall()


def test_a_goal_in_the_open_middle_succeeds_with_its_dead_reckoning_uncertainty(hall):
    driver = simulate(hall, seed=0, people=False)
    driver.run(1.0)
    seen = _go(driver, MIDDLE)
    done = [e for e in seen if isinstance(e, events.NavigationSucceeded)]
    assert len(done) == 1
    assert done[0].uncertainty is not None
    # More than a few centimetres: 10+ m of dead reckoning since the walls went out of range.
    assert done[0].uncertainty.position > 0.1
    assert done[0].attempt.arrival_uncertainty == done[0].uncertainty
    assert driver.stack.estimate.uncertainty == done[0].uncertainty


def test_a_precise_goal_in_the_open_middle_fails_not_localized(hall):
    driver = simulate(hall, seed=0, people=False)
    driver.run(1.0)
    seen = _go(driver, MIDDLE, GoalOptions(max_position_uncertainty=0.05))
    assert driver.stack.navigator.state is NavigationState.FAILED
    attempt = driver.stack.navigator.attempt
    assert attempt is not None
    assert attempt.reason is FailureReason.NOT_LOCALIZED
    assert attempt.arrival_uncertainty is not None
    assert attempt.arrival_uncertainty.position > 0.05
    assert not any(isinstance(e, events.NavigationSucceeded) for e in seen)
    assert isinstance(seen[-1], events.NavigationFailed)


def test_a_precise_goal_near_the_walls_succeeds_within_its_uncertainty(hall):
    driver = simulate(hall, seed=0, people=False)
    driver.run(1.0)
    goal = Pose2D(5.0, 3.0, 0.0)
    seen = _go(driver, goal, GoalOptions(max_position_uncertainty=0.05))
    assert isinstance(seen[-1], events.NavigationSucceeded)
    uncertainty = seen[-1].uncertainty
    assert uncertainty is not None and uncertainty.position <= 0.05
    assert driver.sim.true_pose.distance_to(goal) <= 0.05
