"""Galileo's jacking over real HTTP lifts the simulated cart the robot stands under (E-67),
sets it down when lowered, and leaves a cart heavier than the profile carries on the floor."""

from __future__ import annotations

from polynav.geometry import Twist
from tests.protocols.galileo.conftest import Harness


def _under(galileo: Harness, cart: str) -> None:
    sim = galileo.runtime.simulation
    galileo.runtime.run_between_ticks(
        lambda: sim.teleport("floor1", sim.world.cart(cart).pose))


def test_raising_the_jack_under_a_cart_lifts_it_and_lowering_sets_it_down(
        galileo: Harness) -> None:
    sim = galileo.runtime.simulation
    _under(galileo, "cart_1")
    task = galileo.ok("GET", "/system/jacking_move_to", params={"pose": 100, "speed": 0.03})
    assert task["name"] == "jacking_task"
    galileo.runtime.advance(1.0)  # homing from 12 mm: not up yet
    assert sim.load is None
    galileo.runtime.advance(4.0)
    assert galileo.ok("GET", "/system/jacking_pose")["pose_ratio"] == 1.0
    load = sim.load
    assert load is not None and load.name == "cart_1"
    # Carried: it turns with the robot.
    galileo.runtime.teleop(0.0, 0.5)
    galileo.runtime.advance(1.0)
    assert abs(load.pose.theta) > 0.2
    galileo.ok("GET", "/system/jacking_move_to", params={"pose": 0, "speed": 0.03})
    galileo.runtime.advance(3.0)
    assert sim.load is None
    left = sim.scene.carts.carts["cart_1"].pose
    sim.drive(Twist(0.0, 0.0))
    galileo.runtime.advance(1.0)
    assert sim.scene.carts.carts["cart_1"].pose == left


def test_a_cart_heavier_than_the_profile_carries_stays_on_the_floor(galileo: Harness) -> None:
    sim = galileo.runtime.simulation
    _under(galileo, "cart_2")  # 55 kg; the demo robot carries 50 kg
    galileo.ok("GET", "/system/jacking_move_to", params={"pose": 100, "speed": 0.03})
    galileo.runtime.advance(5.0)
    assert sim.load is None
    assert sim.scene.carts.carts["cart_2"].pose == sim.world.cart("cart_2").pose
