"""Several robot bodies in one scene: one clock, they see and touch each other, people stop."""

from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.errors import InvalidRequest
from polynav.geometry import Pose2D, Twist
from polynav.robot.sim.config import SimConfig
from polynav.robot.sim.scene import Scene
from polynav.robot.sim.simulation import Simulation
from polynav.worlds.world import PersonRoute, World
from tests.unit.robot.sim.ascii_world import ascii_world
from tests.unit.robot.sim.test_simulation import HALL, QUIET


def _hall(**kwargs: object) -> World:
    return ascii_world(HALL, start=Pose2D(1.0, 2.0, 0.0), **kwargs)  # type: ignore[arg-type]


def _pair(world: World, a: Pose2D, b: Pose2D) -> tuple[Simulation, Simulation]:
    scene = Scene(world, QUIET)
    first = Simulation(world, config=QUIET, pose=a, scene=scene, name="r1")
    second = Simulation(world, config=QUIET, pose=b, scene=scene, name="r2", seed=1)
    return first, second


def _range_ahead(sim: Simulation) -> float:
    scan = sim.scan
    assert scan is not None
    ahead = np.abs(scan.angles) < 0.02
    return float(np.min(scan.ranges[ahead]))


def test_bodies_share_one_clock_and_one_step_moves_every_robot() -> None:
    r1, r2 = _pair(_hall(), Pose2D(1.0, 1.0, 0.0), Pose2D(1.0, 3.0, 0.0))
    assert r1.clock is r2.clock and r1.scene is r2.scene
    r1.drive(Twist(0.5, 0.0))
    r2.drive(Twist(0.5, 0.0))
    for _ in range(50):
        r1.step()
    assert r1.clock.now() == pytest.approx(1.0)
    assert r1.true_pose.x > 1.3 and r2.true_pose.x > 1.3
    assert r1.true_pose.x == pytest.approx(r2.true_pose.x)


def test_each_robots_lidar_sees_the_other_robot() -> None:
    r1, r2 = _pair(_hall(), Pose2D(2.0, 2.0, 0.0), Pose2D(5.0, 2.0, math.pi))
    r1.step()
    # The wall straight ahead is at x=9.9; the other robot's near edge is 3 m - its radius away.
    radius = QUIET.robot_radius
    assert _range_ahead(r1) == pytest.approx(3.0 - radius, abs=0.03)
    assert _range_ahead(r2) == pytest.approx(3.0 - radius, abs=0.03)


def test_lone_robot_sees_the_wall_where_a_second_one_would_stand() -> None:
    world = _hall()
    lone = Simulation(world, config=QUIET, pose=Pose2D(2.0, 2.0, 0.0))
    lone.step()
    assert _range_ahead(lone) == pytest.approx(7.9, abs=0.03)


def test_robots_driving_into_each_other_stop_and_record_a_robot_collision() -> None:
    r1, r2 = _pair(_hall(), Pose2D(2.0, 2.0, 0.0), Pose2D(4.0, 2.0, math.pi))
    r1.drive(Twist(0.5, 0.0))
    r2.drive(Twist(0.5, 0.0))
    for _ in range(250):
        r1.step()
    gap = r1.true_pose.distance_to(r2.true_pose) - 2 * QUIET.robot_radius
    assert -1e-6 <= gap < 0.05
    assert [c.obstacle for c in r1.collisions] == ["robot"]
    assert [c.obstacle for c in r2.collisions] == ["robot"]
    # They can always back away from each other.
    stuck_at = r1.true_pose.x
    r2.drive(Twist())
    r1.drive(Twist(-0.3, 0.0))
    for _ in range(50):
        r1.step()
    assert r1.true_pose.x < stuck_at - 0.2


def test_robots_on_other_floors_neither_see_nor_touch_each_other() -> None:
    world = _hall(floors=("ground", "first"))
    scene = Scene(world, QUIET)
    r1 = Simulation(world, config=QUIET, pose=Pose2D(2.0, 2.0, 0.0), scene=scene)
    Simulation(world, config=QUIET, floor="first", pose=Pose2D(2.0, 2.0, 0.0), scene=scene)
    r1.step()
    assert _range_ahead(r1) == pytest.approx(7.9, abs=0.03)


def test_a_person_stops_for_whichever_robot_is_in_the_way() -> None:
    route = PersonRoute(((8.0, 2.0), (1.0, 2.0)), speed=1.0, loop=False)
    r1, r2 = _pair(_hall(people=(route,)), Pose2D(1.0, 3.4, 0.0), Pose2D(5.0, 2.0, 0.0))
    person = r1.scene.floors["ground"].people[0]
    for _ in range(250):
        r1.step()
    # Blocked by r2 (at x=5), the walker stands short of it; r1, off the route, never stops them.
    assert person.x > 5.0 + QUIET.robot_radius + person.radius
    assert person.x < 6.0
    assert r1.collisions == [] and r2.collisions == []


def test_a_robot_cannot_be_placed_on_another() -> None:
    world = _hall()
    scene = Scene(world, QUIET)
    Simulation(world, config=QUIET, pose=Pose2D(2.0, 2.0, 0.0), scene=scene)
    with pytest.raises(InvalidRequest, match="overlaps robot"):
        Simulation(world, config=QUIET, pose=Pose2D(2.3, 2.0, 0.0), scene=scene)
    assert len(scene.bodies) == 1


def test_a_scene_of_another_world_or_another_rate_is_refused() -> None:
    scene = Scene(_hall(), QUIET)
    with pytest.raises(InvalidRequest, match="another world"):
        Simulation(_hall(), config=QUIET, scene=scene)
    world = scene.world
    with pytest.raises(InvalidRequest, match="one rate"):
        Simulation(world, config=SimConfig(physics_rate=100.0), scene=scene,
                   pose=Pose2D(5.0, 2.0, 0.0))
