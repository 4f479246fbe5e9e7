"""Simulated carts and cabins: legs the lidar sees and the base bumps into, the way in between
them, a cart lifted by the jack and carried rigidly (through a lift ride too), set down where
it stands, and a cabin latched with its tag read."""

from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.errors import Conflict
from polynav.geometry import Pose2D, Twist
from polynav.robot.sim.config import SimConfig
from polynav.robot.sim.simulation import Simulation
from polynav.worlds import load_world
from polynav.worlds.carts import entry_pose
from polynav.worlds.world import World


@pytest.fixture(scope="module")
def demo() -> World:
    return load_world("demo")


def _drive(sim: Simulation, twist: Twist, seconds: float) -> None:
    for _ in range(round(seconds / sim.physics_period)):
        sim.drive(twist)
        sim.step()
    sim.drive(Twist())
    sim.step(0.5)


def _beam(sim: Simulation, world_angle: float) -> float:
    scan = sim.scan
    assert scan is not None
    rel = np.vectorize(lambda a: math.remainder(a + sim.true_pose.theta - world_angle,
                                                2.0 * math.pi))(scan.angles)
    return float(scan.ranges[int(np.abs(rel).argmin())])


def test_the_lidar_sees_a_carts_legs_and_the_robot_drives_in_between_and_lifts_it(
        demo: World) -> None:
    cart = demo.cart("cart_1")  # floor 1, (8.6, 2.0), facing east, legs 0.9 x 0.7
    start = entry_pose(cart.pose, cart.length, 0.6)
    sim = Simulation(demo, config=SimConfig(), people=False, floor="floor1", pose=start)
    sim.step(0.2)
    # The back-left leg at (8.15, 2.35) is seen: 0.6 m ahead, 0.35 m to the left, minus 3 cm.
    angle = math.atan2(0.35, 0.6)
    assert _beam(sim, angle) == pytest.approx(math.hypot(0.6, 0.35) - 0.03, abs=0.04)
    _drive(sim, Twist(0.3, 0.0), 1.05 / 0.3)
    assert not sim.collisions
    assert sim.true_pose.distance_to(cart.pose) < 0.1
    assert sim.set_jack_height(0.05) is not None and sim.load is not None
    gap = sim.true_pose.distance_to(cart.pose)  # rigid: the load keeps its place on the robot
    # Carried: it turns and moves with the robot, its legs out of the robot's own scan.
    _drive(sim, Twist(0.0, 0.5), math.pi / 2 / 0.5)
    _drive(sim, Twist(0.3, 0.0), 2.0)
    assert not sim.collisions
    load = sim.load
    assert load is not None
    assert load.pose.distance_to(sim.true_pose) == pytest.approx(gap, abs=1e-6)
    assert abs(math.remainder(load.pose.theta - sim.true_pose.theta, 2 * math.pi)) < 0.02
    assert _beam(sim, sim.true_pose.theta + math.atan2(0.35, 0.45)) > 0.5
    # Set down: it stays where it stands, and the robot drives out.
    left = load.pose
    assert sim.set_jack_height(0.0) is None and sim.load is None
    _drive(sim, Twist(-0.3, 0.0), 1.2 / 0.3)
    assert not sim.collisions
    assert sim.scene.carts.carts["cart_1"].pose == left


def test_a_leg_stops_the_base_and_a_carried_leg_stops_at_a_wall(demo: World) -> None:
    cart = demo.cart("cart_1")
    beside = cart.pose.compose(Pose2D(-0.45, -0.6, 0.0))  # behind the back-right leg's side
    sim = Simulation(demo, config=SimConfig(), people=False, floor="floor1",
                     pose=Pose2D(beside.x, beside.y, math.pi / 2))
    _drive(sim, Twist(0.3, 0.0), 2.0)  # north, into the back-right leg
    assert sim.collisions and sim.collisions[-1].obstacle == "wall"
    # Carried east into the lobby's east wall (x = 10): the front legs hit it first.
    other = Simulation(demo, config=SimConfig(), people=False, floor="floor1",
                       pose=demo.cart("cart_2").pose, scene=sim.scene, name="other")
    assert other.set_jack_height(0.06) is not None
    _drive(other, Twist(0.3, 0.0), 4.0)
    assert other.collisions
    front = max(x for x, _ in other.scene.carts.carried_legs("other", other.true_pose))
    assert 9.85 < front + 0.03 < 10.05


def test_a_carried_cart_rides_the_lift(demo: World) -> None:
    sim = Simulation(demo, config=SimConfig(), people=False, floor="floor1",
                     pose=demo.cart("cart_1").pose)
    assert sim.set_jack_height(0.06) is not None
    inside = demo.floor("floor2").point("lift_1_inside").pose
    sim.teleport("floor2", inside)
    load = sim.load
    assert load is not None and load.floor == "floor2"
    assert load.pose.distance_to(inside) < 1e-9
    assert sim.scene.carts.legs("floor1").shape == (4, 3)  # cart_2 only
    assert sim.scene.carts.legs("floor2").shape == (8, 3)  # cabin_1 and cart_1


def test_a_cabin_latches_only_when_the_robot_stands_in_it(demo: World) -> None:
    cabin = demo.cart("cabin_1")
    sim = Simulation(demo, config=SimConfig(), people=False, floor="floor2",
                     pose=entry_pose(cabin.pose, cabin.length, 0.6))
    assert sim.cabin_tag() is None
    with pytest.raises(Conflict, match="no cabin"):
        sim.latch()
    assert sim.set_jack_height(0.06) is None  # a cabin is latched, not jacked
    _drive(sim, Twist(0.3, 0.0), 1.05 / 0.3)
    assert not sim.collisions
    assert sim.cabin_tag() == "CAB-0001"
    assert sim.latch().name == "cabin_1"
    _drive(sim, Twist(-0.3, 0.0), 1.0)
    assert sim.load is not None and sim.load.pose.distance_to(cabin.pose) > 0.2
    assert sim.unlatch() is not None and sim.load is None
