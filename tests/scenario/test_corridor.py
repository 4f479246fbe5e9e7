"""Localization where the scan does not pin the pose down: a 100 m x 1 m corridor, driven end to
end by the navigator on simulated time, stays TRACKING (odometry carries the pose along the
corridor, the walls across it) and arrives within 0.1 m."""

from __future__ import annotations

import numpy as np

from polynav.geometry import Pose2D
from polynav.localization.degeneracy import translation_constraint
from polynav.localization.interface import LocalizationState
from polynav.localization.likelihood_field import build_likelihood_field
from polynav.maps.map import Map, MapInfo
from polynav.nav.attempt import NavigationState
from polynav.runtime.sim_driver import simulate
from polynav.worlds.world import World, WorldFloor

RES = 0.05


def _corridor(length: float = 100.0, width: float = 1.0) -> Map:
    wall = 4  # cells
    w, h = int(length / RES) + 2 * wall, int(width / RES) + 2 * wall
    data = np.full((h, w), 100, dtype=np.int8)
    data[wall:-wall, wall:-wall] = 0
    return Map(MapInfo(RES, w, h, Pose2D(-wall * RES, -wall * RES, 0.0)), data)


def _room(size: float = 6.0) -> Map:
    wall = 4
    n = int(size / RES) + 2 * wall
    data = np.full((n, n), 100, dtype=np.int8)
    data[wall:-wall, wall:-wall] = 0
    return Map(MapInfo(RES, n, n, Pose2D(-wall * RES, -wall * RES, 0.0)), data)


def _ring(radius: float, count: int = 360) -> np.ndarray:
    """Endpoints of a lidar in the middle of a corridor or a room (robot frame), ray-cast."""
    angles = np.linspace(-np.pi, np.pi, count, endpoint=False)
    return np.column_stack((np.cos(angles), np.sin(angles))) * radius


def _endpoints(grid: Map, pose: Pose2D, max_range: float = 12.0) -> np.ndarray:
    occupied = grid.data >= 65
    out = []
    for a in np.linspace(-np.pi, np.pi, 360, endpoint=False):
        for r in np.arange(0.05, max_range, RES / 2):
            x, y = pose.x + r * np.cos(a), pose.y + r * np.sin(a)
            ix, iy = grid.info.world_to_cell(x, y)
            if not grid.info.contains(ix, iy) or occupied[iy, ix]:
                out.append((r * np.cos(a), r * np.sin(a)))
                break
    return np.array(out)


def test_the_along_corridor_direction_is_unconstrained_and_a_room_corner_is_not() -> None:
    corridor = _corridor()
    field = build_likelihood_field(corridor)
    middle = Pose2D(50.0, 0.5, 0.0)
    c = translation_constraint(field, _endpoints(corridor, middle), middle, inlier_distance=0.1)
    assert c.degenerate(0.1)
    assert abs(c.weak_direction[0]) > 0.99  # along x, the corridor
    room = _room()
    field = build_likelihood_field(room)
    corner = Pose2D(1.0, 1.0, 0.3)
    c = translation_constraint(field, _endpoints(room, corner), corner, inlier_distance=0.1)
    assert not c.degenerate(0.1) and c.weak > 0.2 * c.strong


def test_a_100_m_corridor_is_driven_end_to_end_without_getting_lost() -> None:
    grid = _corridor()
    floor = WorldFloor("corridor", 1, "corridor", grid, (), None, ())
    start, goal = Pose2D(1.0, 0.5, 0.0), Pose2D(99.0, 0.5, 0.0)
    driver = simulate(World("corridor", (floor,), "corridor", start), seed=5, people=False)
    states: set[LocalizationState] = set()
    driver.stack.go_to(goal, driver.now)
    while not driver.stack.navigator.state.finished and driver.now < 400.0:
        driver.step()
        states.add(driver.stack.estimate.state)
    attempt = driver.stack.navigator.attempt
    assert attempt is not None and attempt.state is NavigationState.SUCCEEDED, attempt
    assert LocalizationState.LOST not in states
    assert driver.sim.true_pose.distance_to(goal) <= 0.1
    assert driver.sim.collisions == []
