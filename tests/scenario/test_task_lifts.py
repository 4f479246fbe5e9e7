"""A task that rides a lift itself, on the demo building and simulated time (issue 32).

The document's lift example as a behavior tree (galileo-tasks-bt-ws §7.5(a)): a restart
sequence around "cancel the lift request, move to the lift door" and "call the lift, enter it",
the second a fallback that cancels and backs off when the car is occupied; then wait for the
car to reach floor 2 and leave it. Floor 1 to floor 2 through lift_1: it completes when the car
is free and calls again (the restart) while the car arrives full. The gateway's enter/leave
requests and acknowledgements, an occupied car and bad parameters beside.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest

from polynav.errors import InvalidRequest
from polynav.robot.lift import LiftRequest
from polynav.runtime import events
from polynav.runtime.config import RuntimeConfig
from polynav.runtime.robot_runtime import RobotRuntime
from polynav.store.site_store import SiteStore
from polynav.worlds.world import World

POSITION_TOLERANCE = 0.15

CANCEL_REQUEST = {"type": "lbt_elevator_ack_action", "name": "cancel lift request"}

#: §7.5(a) in the JSON form: "cancel lift request" is the acknowledgement with no enter
#: pending (it gives any car back); "enter elevator" drives to the car's inside point.
LIFT_TREE: dict[str, Any] = {
    "name": "floor1 to floor2 by lift_1", "control_type": "sequence", "sub_tasks": [
        {"name": "get into the lift", "control_type": "restart_sequence", "sub_tasks": [
            {"name": "to the door", "control_type": "sequence", "sub_tasks": [
                CANCEL_REQUEST,
                {"type": "nav_action", "point": "lift_1_outside",
                 "name": "move to 1F elevator door"}]},
            {"name": "call and enter", "control_type": "fallback", "sub_tasks": [
                {"control_type": "sequence", "sub_tasks": [
                    {"type": "elevator_req_action", "direction": "up", "lift": "lift_1",
                     "name": "call elevator"},
                    {"type": "nav_action", "point": "lift_1_inside",
                     "name": "enter elevator"}]},
                {"control_type": "force_fail", "sub_tasks": [
                    {"name": "cancel and back off", "control_type": "sequence", "sub_tasks": [
                        CANCEL_REQUEST,
                        {"type": "local_move_action", "distance": -0.5, "name": "back off"},
                        {"type": "sleep_action", "wait_time": 5}]}]}]}]},
        {"type": "elevator_req_action", "level": 2, "name": "wait for elevator to reach 2F"},
        {"type": "switch_map_action", "map": "floor2", "point": "lift_1_inside"},
        {"type": "nav_action", "point": "lift_1_outside",
         "name": "exit elevator, arrive at 2F elevator door"},
        {"type": "lbt_elevator_ack_action", "name": "release the lift"}]}


@pytest.fixture
def runtime(world: World, store: SiteStore) -> Iterator[RobotRuntime]:
    rt = RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False, seed=3))
    rt.start_navigation("floor1")
    rt.advance(0.5)
    yield rt


def _ended(rt: RobotRuntime, task_id: str, timeout: float) -> str:
    assert rt.advance_until(
        lambda: rt.tasks.get(task_id)["state"] not in ("WAITTING", "WORKING"), timeout)
    return str(rt.tasks.get(task_id)["state"])


def _at(rt: RobotRuntime, store: SiteStore, floor: str, point: str) -> float:
    goal = store.point(floor, point).pose
    assert rt.simulation.floor == floor
    return rt.simulation.true_pose.distance_to(goal)


def _call_failures(changes: list[events.RuntimeEvent]) -> list[str]:
    """Why "call elevator" failed, each time it did (an action's ``node_kind`` is
    ``action``: the node is told by its result)."""
    return [e.result for e in changes if isinstance(e, events.TaskChanged)
            and e.state == "FAIL" and e.result.startswith("lift ")]


def test_the_lift_tree_completes_when_the_lift_is_free(runtime: RobotRuntime,
                                                       store: SiteStore) -> None:
    sub = runtime.bus.subscribe(100_000)
    task = runtime.tasks.create(LIFT_TREE, start=True)
    assert _ended(runtime, task["id"], 600.0) == "COMPLETE", runtime.tasks.get(task["id"])
    assert _at(runtime, store, "floor2", "lift_1_outside") < POSITION_TOLERANCE
    assert runtime.status().map == "floor2"
    changes = sub.get_nowait()
    assert _call_failures(changes) == []
    assert any(isinstance(e, events.TaskChanged) and e.state == "COMPLETE"
               and e.result == "lift lift_1 given back" for e in changes)
    done = runtime.tasks.get(task["id"])
    assert (done["blackboard"]["lift.car"], done["blackboard"]["lift.floor"]) == (
        "lift_1", "floor2")
    assert runtime.lift("lift_1").state().session_id == ""  # given back
    assert runtime.simulation.collisions == []


def test_the_lift_tree_calls_again_while_the_car_is_occupied(runtime: RobotRuntime,
                                                             store: SiteStore) -> None:
    car = runtime.simulation.scene.lifts["lift_1"]
    car.board_people(2)  # capacity 2: full
    sub = runtime.bus.subscribe(100_000)
    seen: list[events.RuntimeEvent] = []

    def failed_twice() -> bool:
        seen.extend(sub.get_nowait())
        return len(_call_failures(seen)) >= 2

    task = runtime.tasks.create(LIFT_TREE, start=True)
    assert runtime.advance_until(failed_twice, 600.0)
    assert set(_call_failures(seen)) == {"lift lift_1 is full"}
    assert runtime.simulation.floor == "floor1"
    assert runtime.tasks.get(task["id"])["state"] == "WORKING"
    assert runtime.lift("lift_1").state().session_id == ""  # not held while it backs off
    car.board_people(-2)  # they get out
    assert _ended(runtime, task["id"], 600.0) == "COMPLETE"
    assert _at(runtime, store, "floor2", "lift_1_outside") < POSITION_TOLERANCE


def test_a_car_another_session_holds_is_occupied_the_call_fails(
        runtime: RobotRuntime) -> None:
    runtime.request_lift("lift_1", LiftRequest("operator", "floor3"))
    task = runtime.tasks.create({"name": "call", "sub_tasks": [
        {"type": "elevator_req_action", "direction": "down", "lift": "lift_1"}]}, start=True)
    assert _ended(runtime, task["id"], 5.0) == "FAIL"
    leaf = runtime.tasks.get(task["id"])["tree"]["children"][0]
    assert leaf["state"] == "FAIL" and "occupied" in leaf["result"]
    assert runtime.lift("lift_1").state().session_id == "operator"


def test_a_car_that_does_not_come_in_time_fails_and_is_given_back(
        runtime: RobotRuntime) -> None:
    task = runtime.tasks.create({"name": "call", "sub_tasks": [
        {"type": "elevator_req_action", "level": 3, "lift": "lift_1", "timeout": 2}]},
        start=True)
    assert _ended(runtime, task["id"], 10.0) == "FAIL"
    assert "did not come within 2 s" in runtime.tasks.get(task["id"])["tree"]["children"][0][
        "result"]
    assert runtime.lift("lift_1").state().session_id == ""


def test_cancelling_a_call_gives_the_car_back(runtime: RobotRuntime) -> None:
    task = runtime.tasks.create({"name": "call", "sub_tasks": [
        {"type": "elevator_req_action", "level": 3}]}, start=True)
    runtime.advance(1.0)
    assert runtime.lift("lift_1").state().session_id == runtime.robot_id  # the nearest car
    runtime.tasks.cancel(task["id"])
    assert runtime.lift("lift_1").state().session_id == ""


def test_the_gateway_requests_and_acknowledgements_ride_the_car(
        runtime: RobotRuntime, store: SiteStore) -> None:
    tree = {"name": "lbt", "sub_tasks": [
        {"type": "nav_action", "point": "lift_1_outside"},
        {"type": "lbt_elevator_req_action", "from_level": 1, "to_level": 2, "cmd": "enter"},
        {"type": "nav_action", "point": "lift_1_inside"},
        {"type": "lbt_elevator_ack_action"},
        {"type": "lbt_elevator_req_action", "from_level": 1, "to_level": 2, "cmd": "leave"},
        {"type": "switch_map_action", "map": "floor2", "point": "lift_1_inside"},
        {"type": "nav_action", "point": "lift_1_outside"},
        {"type": "lbt_elevator_ack_action"}]}
    task = runtime.tasks.create(tree, start=True)
    assert _ended(runtime, task["id"], 600.0) == "COMPLETE", runtime.tasks.get(task["id"])
    done = runtime.tasks.get(task["id"])
    results = [c["result"] for c in done["tree"]["children"]]
    assert results[3] == "lift lift_1 sent to level 2"
    assert results[7] == "lift lift_1 given back"
    assert done["blackboard"]["lbt.cmd"] == ""
    assert _at(runtime, store, "floor2", "lift_1_outside") < POSITION_TOLERANCE
    assert runtime.lift("lift_1").state().session_id == ""


def test_a_lift_held_by_a_task_is_given_back_when_the_task_ends(runtime: RobotRuntime) -> None:
    task = runtime.tasks.create({"name": "hold", "sub_tasks": [
        {"type": "elevator_req_action", "direction": "up"}, {"type": "wait_req_action"}]},
        start=True)
    assert runtime.advance_until(
        lambda: runtime.tasks.get(task["id"])["tree"]["children"][0]["state"] == "COMPLETE",
        60.0)
    held = runtime.held_lift()
    assert held is not None and held.floor == "floor1"
    assert held.car == runtime.tasks.get(task["id"])["blackboard"]["lift.car"]
    assert runtime.lift(held.car).state().session_id == runtime.robot_id
    runtime.tasks.cancel(task["id"])
    assert runtime.lift(held.car).state().session_id == ""
    assert runtime.held_lift() is None


@pytest.mark.parametrize(("action", "match"), [
    ({"type": "elevator_req_action"}, "level"),
    ({"type": "elevator_req_action", "level": 2, "direction": "up"}, "not both"),
    ({"type": "elevator_req_action", "direction": "sideways"}, "direction"),
    ({"type": "lbt_elevator_req_action", "from_level": 1, "to_level": 2, "cmd": "jump"}, "cmd"),
    ({"type": "lbt_elevator_req_action", "to_level": 2, "cmd": "enter"}, "from_level"),
])
def test_bad_lift_parameters_are_refused_at_create(runtime: RobotRuntime,
                                                   action: dict[str, Any], match: str) -> None:
    with pytest.raises(InvalidRequest, match=match):
        runtime.tasks.create({"name": "bad", "sub_tasks": [action]})


@pytest.mark.parametrize(("action", "match"), [
    ({"type": "elevator_req_action", "level": 9}, "no floor of the site is at level 9"),
    ({"type": "elevator_req_action", "level": 3, "lift": "lift_2"}, "does not serve floor3"),
    ({"type": "elevator_req_action", "direction": "up", "lift": "lift_9"}, "lift_9"),
])
def test_a_lift_that_cannot_be_named_is_an_error(runtime: RobotRuntime, action: dict[str, Any],
                                                  match: str) -> None:
    task = runtime.tasks.create({"name": "bad", "sub_tasks": [action]}, start=True)
    assert _ended(runtime, task["id"], 2.0) == "ERROR"
    assert match in runtime.tasks.get(task["id"])["tree"]["children"][0]["result"]
