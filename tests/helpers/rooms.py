"""Walled rooms drawn from boxes and posts on a 0.05 m grid, for whole missions at close quarters.

The inside of a room starts at (0.2, 0.2), inside 0.2 m walls. A mission may run on a map that
differs from the simulator's ground truth (a post the map does not have).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from polynav.geometry import Pose2D
from polynav.maps.map import Map
from polynav.nav import events
from polynav.nav.stack import NavigationStack, stack_config_for
from polynav.robot.profile import RobotProfile
from polynav.robot.sim.config import SimConfig
from polynav.robot.sim.simulation import Simulation
from polynav.runtime.sim_driver import SimDriver
from polynav.worlds.world import World, WorldFloor

RES = 0.05  # [m]
WALL = 0.2  # [m]

Box = tuple[float, float, float, float]


def room(length: float, width: float, boxes: Sequence[Box] = (),
         posts: Sequence[tuple[float, float]] = (), post_radius: float = 0.06) -> Map:
    """A room ``length`` x ``width`` [m] with wall boxes (x0, y0, x1, y1) and round posts."""
    nx, ny = round((length + 2 * WALL) / RES), round((width + 2 * WALL) / RES)
    w = round(WALL / RES)
    occupied = np.ones((ny, nx), dtype=bool)
    occupied[w:ny - w, w:nx - w] = False
    iy, ix = np.mgrid[0:ny, 0:nx]
    cx, cy = (ix + 0.5) * RES, (iy + 0.5) * RES
    for x0, y0, x1, y1 in boxes:
        occupied |= (cx >= x0) & (cx <= x1) & (cy >= y0) & (cy <= y1)
    for px, py in posts:
        occupied |= np.hypot(cx - px, cy - py) <= post_radius
        occupied[int(py // RES), int(px // RES)] = True
    return Map.from_occupied(occupied, resolution=RES)


def drive(truth: Map, start: Pose2D, profile: RobotProfile, *, seed: int = 0,
          mapped: Map | None = None) -> tuple[SimDriver, list[events.NavigationEvent]]:
    """The simulated robot at ``start`` in ``truth``, navigating on ``mapped`` (default: the
    truth), settled for a second; and the list its navigation events go to."""
    floor = WorldFloor(name="floor1", level=1, map_name="room", map=truth, points=(), lift=None,
                       people=())
    world = World(name="room", floors=(floor,), start_floor="floor1", start_pose=start)
    sim = Simulation(world, config=profile.sim_config(SimConfig()), seed=seed, people=False)
    seen: list[events.NavigationEvent] = []
    stack = NavigationStack(sim.robot, mapped or truth, config=stack_config_for(profile),
                            on_event=seen.append)
    stack.initialize(sim.true_pose, sim.clock.now())
    driver = SimDriver(sim, stack)
    driver.run(1.0)
    return driver, seen


def go(driver: SimDriver, goal: Pose2D, timeout: float) -> None:
    """Send ``goal`` and run until the attempt ends (asserting it does within ``timeout``)."""
    driver.stack.go_to(goal, driver.now)
    assert driver.run_until(lambda: driver.stack.navigator.state.finished, timeout=timeout)


def retries(seen: Sequence[events.NavigationEvent]) -> list[tuple[str, str]]:
    """(cause, recovery) of every retry seen."""
    return [(e.cause, e.recovery) for e in seen if isinstance(e, events.NavigationRetry)]
