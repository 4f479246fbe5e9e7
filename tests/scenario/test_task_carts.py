"""Cart task actions on the simulated demo robot (issue #38 item 2): a task docks to cart_1,
carries it to a point and leaves it there; a dock with nothing to dock to is an ERROR that
changes nothing; a too heavy cart likewise; bad parameters are refused at create."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from polynav.errors import InvalidRequest
from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds.world import World


@pytest.fixture
def runtime(world: World, tmp_path: Path) -> Iterator[RobotRuntime]:
    with SiteStore.open(tmp_path / "data", seed_world=world) as store:
        rt = RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False, seed=4))
        rt.start_navigation("floor1")
        rt.advance(0.5)
        yield rt


def _run(rt: RobotRuntime, *actions: dict[str, Any], timeout: float = 120.0) -> dict[str, Any]:
    task = rt.tasks.create({"name": "t", "sub_tasks": list(actions)}, start=True)
    assert rt.advance_until(
        lambda: rt.tasks.get(task["id"])["state"] not in ("WAITTING", "WORKING"), timeout)
    return rt.tasks.get(task["id"])


def test_a_task_docks_carries_and_leaves_a_cart(runtime: RobotRuntime,
                                                 world: World) -> None:
    task = _run(runtime, {"type": "dock_cart_action", "cart": "cart_1"},
                {"type": "leave_cart_action", "point": "front_desk"})
    assert task["state"] == "COMPLETE", task["tree"]
    assert task["blackboard"]["cart.name"] == "cart_1"
    sim = runtime.simulation
    assert sim.load is None
    cart = sim.scene.carts.carts["cart_1"]
    goal = runtime.store.point("floor1", "front_desk").pose
    assert cart.pose.distance_to(goal) < 0.1
    assert cart.pose.distance_to(world.cart("cart_1").pose) > 3.0


def test_a_dock_to_nothing_or_too_heavy_is_an_error_that_changes_nothing(
        runtime: RobotRuntime) -> None:
    before = runtime.simulation.true_pose
    for action, words in (({"type": "dock_cart_action", "point": "lobby"}, "nothing to dock"),
                          ({"type": "dock_cart_action", "cart": "cart_2"}, "weighs 55 kg")):
        task = _run(runtime, action, timeout=5.0)
        leaf = task["tree"]["children"][0]
        assert task["state"] == "ERROR" and words in leaf["result"], leaf
    assert runtime.simulation.true_pose.distance_to(before) < 0.01
    assert runtime.simulation.load is None


def test_bad_cart_parameters_are_refused_at_create(runtime: RobotRuntime) -> None:
    for action in ({"type": "dock_cart_action"},
                   {"type": "dock_cart_action", "cart": "cart_1", "point": "lobby"},
                   {"type": "leave_cart_action", "point": ""}):
        with pytest.raises(InvalidRequest):
            runtime.tasks.create({"name": "t", "sub_tasks": [action]})
