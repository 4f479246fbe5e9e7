"""Carts and cabins end to end on simulated time (issue #38 item 2), judged on ground truth.

A cart docked by sight (standing 8 cm and 3 degrees off where the robot believes it is),
lifted, carried through lift_1 to floor 2 and left at a point within 5 cm / 0.05 rad; a cabin
with another id refused; a dock with nothing to dock to and a cart heavier than the profile
carries refused at once, nothing changed; a leave whose way out is blocked retried.
"""

from __future__ import annotations

import dataclasses
import math

import pytest

from polynav.errors import Conflict, InvalidRequest
from polynav.geometry import Pose2D
from polynav.runtime.cart_events import CartAction, CartFailure, CartStep
from polynav.runtime.config import RuntimeConfig
from polynav.runtime.robot_runtime import RobotRuntime
from polynav.store.site_store import SiteStore
from polynav.worlds import load_world
from polynav.worlds.carts import CartKind, WorldCart
from polynav.worlds.world import World

# A cart in floor 1's lift lobby, facing north; the robot starts in the corridor south of it.
BELIEVED = Pose2D(36.0, 15.2, math.pi / 2)
TRUE = Pose2D(36.06, 15.25, math.pi / 2 + math.radians(3.0))
START = Pose2D(36.0, 12.0, math.pi / 2)


@pytest.fixture(scope="module")
def world() -> World:
    demo = load_world("demo")
    lobby = WorldCart("trolley", CartKind.CART, "floor1", TRUE, mass=30.0)
    return dataclasses.replace(demo, carts=(*demo.carts, lobby), start_pose=START)


@pytest.fixture
def runtime(world: World, store: SiteStore) -> RobotRuntime:
    rt = RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False, seed=5))
    rt.start_navigation("floor1", pose=START)
    rt.advance(0.5)
    # Where the site believes the trolley stands: 8 cm and 3 degrees off the truth.
    rt.carts._known["trolley"] = ("floor1", BELIEVED)
    return rt


def _actions(events: list[object]) -> list[tuple[str, str, CartStep, CartFailure | None]]:
    return [(e.action, e.cart, e.step, e.reason) for e in events if isinstance(e, CartAction)]


def _done(runtime: RobotRuntime) -> bool:
    return not runtime.carts.busy


def test_a_cart_docked_carried_across_a_lift_and_left_at_a_point(
        runtime: RobotRuntime, store: SiteStore) -> None:
    sub = runtime.bus.subscribe(10_000)
    runtime.carts.dock(cart="trolley")
    assert runtime.advance_until(lambda: _done(runtime), 120.0)
    sim = runtime.simulation
    load = sim.load
    assert load is not None and load.name == "trolley", _actions(sub.get_nowait())
    assert sim.true_pose.distance_to(TRUE) < 0.05
    assert runtime.carts.status()["load"] == {"name": "trolley", "kind": "cart", "mass": 30.0}
    runtime.advance(0.2)
    assert runtime.status().to_dict()["load"] == {"name": "trolley", "kind": "cart",
                                                  "mass": 30.0}
    runtime.carts.leave(point="initial", map_name="floor2")
    assert runtime.advance_until(lambda: _done(runtime), 400.0)
    got = _actions(sub.get_nowait())
    assert got[-1] == ("leave", "trolley", CartStep.SUCCEEDED, None), got
    assert sim.load is None and sim.floor == "floor2"
    cart = sim.scene.carts.carts["trolley"]
    goal = store.point("floor2", "initial").pose
    assert cart.floor == "floor2"
    assert cart.pose.distance_to(goal) <= 0.05, cart.pose
    assert abs(math.remainder(cart.pose.theta - goal.theta, 2 * math.pi)) <= 0.05
    assert sim.collisions == []
    assert runtime.carts.status()["load"] is None
    assert "load" not in runtime.status().to_dict()


def test_nothing_to_dock_to_and_a_cart_too_heavy_are_refused_and_nothing_changes(
        runtime: RobotRuntime) -> None:
    before = runtime.simulation.true_pose
    with pytest.raises(InvalidRequest, match="nothing to dock to"):
        runtime.carts.dock(point="corridor_east")
    with pytest.raises(InvalidRequest, match="no cart or cabin 'sofa'"):
        runtime.carts.dock(cart="sofa")
    with pytest.raises(Conflict, match="weighs 55 kg: this robot carries at most 50 kg"):
        runtime.carts.dock(cart="cart_2")
    with pytest.raises(Conflict, match="carries no cart"):
        runtime.carts.leave()
    runtime.advance(1.0)
    assert not runtime.carts.busy and runtime.status().attempt_id is None
    assert runtime.simulation.true_pose.distance_to(before) < 0.01


def test_a_cabin_with_another_id_is_refused_and_the_robot_backs_out(
        world: World, store: SiteStore) -> None:
    cabin = world.cart("cabin_1")  # floor 2, housekeeping; its tag reads CAB-0001
    rt = RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False, seed=5))
    rt.start_navigation("floor2", point="housekeeping")
    rt.advance(0.5)
    sub = rt.bus.subscribe(1000)
    rt.carts.dock(cart="cabin_1", cabin_id="CAB-0002")
    assert rt.advance_until(lambda: _done(rt), 120.0)
    got = _actions(sub.get_nowait())
    assert got[-1] == ("dock", "cabin_1", CartStep.FAILED, CartFailure.WRONG_CABIN), got
    sim = rt.simulation
    assert sim.load is None and rt.carts.load is None
    assert sim.scene.carts.carts["cabin_1"].pose == cabin.pose
    assert sim.true_pose.distance_to(cabin.pose) > 0.5  # backed out
    # The right id: latched.
    rt.carts.dock(cart="cabin_1", cabin_id="CAB-0001")
    assert rt.advance_until(lambda: _done(rt), 120.0)
    load = sim.load
    assert load is not None and load.name == "cabin_1"
    assert sim.collisions == []


def test_a_leave_whose_way_out_is_blocked_is_retried(runtime: RobotRuntime) -> None:
    runtime.carts.dock(cart="trolley")
    assert runtime.advance_until(lambda: _done(runtime), 120.0)
    assert runtime.carts.load is not None
    sub = runtime.bus.subscribe(1000)
    sim = runtime.simulation
    runtime.carts.leave()
    # The e-stop holds the robot under the cart while it tries to drive out.
    assert runtime.advance_until(
        lambda: (runtime.carts.status()["action"] or {}).get("phase") == "exiting", 30.0)
    sim.press_estop()
    assert runtime.advance_until(lambda: any(
        e.step is CartStep.RETRIED for e in sub.get_nowait() if isinstance(e, CartAction)), 10.0)
    sim.release_estop()
    assert runtime.advance_until(lambda: _done(runtime), 30.0)
    assert sim.load is None and runtime.carts.load is None
    cart = sim.scene.carts.carts["trolley"]
    assert sim.true_pose.distance_to(cart.pose) > 0.8
