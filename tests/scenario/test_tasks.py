"""The task engine on the simulated demo robot: trees of real actions, on simulated time.

Navigation actions drive the robot there (the controller, on the real costmap), pause stops it
and resume reaches the same goal, cancel leaves it idle, a fallback branches when a goal cannot
be reached, and the blackboard carries values from the root and from earlier nodes.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from pathlib import Path

import pytest

from polynav.errors import Conflict, InvalidRequest, NotFound
from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds.world import World


@pytest.fixture
def runtime(world: World, tmp_path: Path) -> Iterator[RobotRuntime]:
    with SiteStore.open(tmp_path / "data", seed_world=world) as store:
        rt = RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False))
        rt.start_navigation("floor1")
        rt.advance(0.5)
        yield rt


def _until_ended(rt: RobotRuntime, task_id: str, timeout: float = 240.0) -> str:
    assert rt.advance_until(
        lambda: rt.tasks.get(task_id)["state"] not in ("WAITTING", "WORKING"), timeout)
    return str(rt.tasks.get(task_id)["state"])


def _true_pose_error(rt: RobotRuntime, x: float, y: float) -> float:
    truth = rt.simulation.true_pose
    return math.hypot(truth.x - x, truth.y - y)


def test_three_navigation_actions_reach_each_point(runtime: RobotRuntime) -> None:
    points = [(5.5, 12.5, 0.0), (13.5, 12.4, 0.0), (8.0, 8.5, math.pi / 2)]
    tree = {"name": "three", "sub_tasks": [
        {"type": "nav_action", "x": x, "y": y, "theta": t} for x, y, t in points]}
    task = runtime.tasks.create(tree)
    assert task["state"] == "WAITTING"
    task = runtime.tasks.start(task["id"])
    reached = []
    for i, (x, y, _) in enumerate(points):
        assert runtime.advance_until(
            lambda i=i: runtime.tasks.get(task["id"])["tree"]["children"][i]["state"]
            != "WORKING" and runtime.tasks.get(task["id"])["tree"]["children"][i]["state"]
            != "WAITTING", 120.0)
        reached.append(_true_pose_error(runtime, x, y))
    assert _until_ended(runtime, task["id"]) == "COMPLETE"
    assert max(reached) < 0.1
    assert runtime.status().navigation_state == "succeeded"


def test_a_fallback_over_an_unreachable_goal_goes_to_the_real_point(
        runtime: RobotRuntime) -> None:
    tree = {"name": "fallback", "control_type": "fallback", "sub_tasks": [
        {"type": "nav_action", "x": -50.0, "y": -50.0, "theta": 0.0},  # off the map
        {"type": "nav_action", "point": "lobby"}]}
    task = runtime.tasks.create(tree, start=True)
    assert _until_ended(runtime, task["id"]) == "COMPLETE"
    first, second = runtime.tasks.get(task["id"])["tree"]["children"]
    assert first["state"] == "FAIL" and first["result"]
    assert second["state"] == "COMPLETE"
    assert _true_pose_error(runtime, 5.5, 12.5) < 0.1


def test_pause_stops_the_robot_and_resume_reaches_the_same_goal(
        runtime: RobotRuntime) -> None:
    task = runtime.tasks.create({"name": "go", "sub_tasks": [
        {"type": "nav_action", "point": "corridor_east"}]}, start=True)
    runtime.advance(6.0)
    assert runtime.status().navigation_state == "running"
    paused = runtime.tasks.pause(task["id"])
    assert paused["state"] == "PAUSED" and paused["tree"]["children"][0]["state"] == "PAUSED"
    runtime.advance(3.0)  # time to brake
    assert runtime.status().navigation_state == "paused"
    still = runtime.simulation.true_pose
    runtime.advance(5.0)
    assert math.hypot(runtime.simulation.true_pose.x - still.x,
                      runtime.simulation.true_pose.y - still.y) < 0.02
    with pytest.raises(Conflict):
        runtime.tasks.pause(task["id"])
    runtime.tasks.resume(task["id"])
    assert _until_ended(runtime, task["id"]) == "COMPLETE"
    assert _true_pose_error(runtime, 29.0, 12.4) < 0.1


def test_cancel_leaves_the_robot_idle_and_the_task_cancelled(runtime: RobotRuntime) -> None:
    task = runtime.tasks.create({"name": "go", "sub_tasks": [
        {"type": "nav_action", "point": "corridor_east"},
        {"type": "sleep_action", "wait_time": 1}]}, start=True)
    runtime.advance(4.0)
    done = runtime.tasks.cancel(task["id"])
    assert done["state"] == "CANCELLED"
    assert [c["state"] for c in done["tree"]["children"]] == ["CANCELLED", "CANCELLED"]
    runtime.advance(2.0)
    assert runtime.status().navigation_state == "canceled"
    still = runtime.simulation.true_pose
    runtime.advance(3.0)
    assert math.hypot(runtime.simulation.true_pose.x - still.x,
                      runtime.simulation.true_pose.y - still.y) < 0.02
    assert runtime.tasks.running() is None


def test_the_blackboard_gives_root_values_and_what_earlier_nodes_wrote(
        runtime: RobotRuntime) -> None:
    tree = {"name": "talk", "control_type": "sequence",
            "blackboard": {"greeting": "hello from the root"},
            "sub_tasks": [
                {"type": "tts_action", "text": "{greeting}"},
                {"type": "nav_action", "point": "lobby"},
                {"type": "tts_action", "text": "arrived at x={nav.x}"},
                {"type": "sleep_action", "wait_time": "{pause}"}]}
    task = runtime.tasks.create({**tree, "blackboard": {**tree["blackboard"], "pause": 1.5}},
                                start=True)
    speaker = runtime.peripherals.devices.speaker
    runtime.advance(0.2)
    assert speaker.text == "hello from the root"
    assert _until_ended(runtime, task["id"]) == "COMPLETE"
    spoken = runtime.tasks.get(task["id"])["blackboard"]
    assert speaker.text == spoken["tts.text"]
    assert spoken["tts.text"].startswith("arrived at x=5.")
    said = [c["params"]["text"] for c in runtime.tasks.get(task["id"])["tree"]["children"]
            if c["type"] == "tts_action"]
    assert said == ["{greeting}", "arrived at x={nav.x}"]  # the stored parameters unchanged


def test_a_wait_is_released_by_a_trigger(runtime: RobotRuntime) -> None:
    task = runtime.tasks.create({"name": "wait", "sub_tasks": [
        {"type": "wait_req_action"}, {"type": "sleep_action", "wait_time": 0.5}]}, start=True)
    runtime.advance(5.0)
    assert runtime.tasks.get(task["id"])["tree"]["children"][0]["state"] == "WORKING"
    assert runtime.tasks.trigger_waits() == 1
    assert _until_ended(runtime, task["id"], 5.0) == "COMPLETE"
    assert runtime.tasks.get(task["id"])["blackboard"]["wait_req.triggered"] is True


def test_settings_changed_by_a_task_are_restored_when_it_ends(runtime: RobotRuntime) -> None:
    before = runtime.settings().to_dict()["max_linear_velocity"]
    task = runtime.tasks.create({"name": "slow", "sub_tasks": [
        {"type": "change_setting_action", "settings": {"max_linear_velocity": 0.3},
         "init_settings": {"max_linear_velocity": before}},
        {"type": "wait_req_action"}]}, start=True)
    runtime.advance(0.5)
    assert runtime.settings().to_dict()["max_linear_velocity"] == pytest.approx(0.3)
    runtime.tasks.cancel(task["id"])
    assert runtime.settings().to_dict()["max_linear_velocity"] == pytest.approx(before)


@pytest.mark.parametrize(("tree", "match"), [
    ({"name": "x", "sub_tasks": [{"type": "fly_action"}]}, "unknown action type"),
    ({"name": "x", "sub_tasks": [{"type": "sleep_action", "wait_time": -1}]}, "wait_time"),
    ({"name": "x", "sub_tasks": ["missing"]}, "no node named"),
    ({"name": "x", "nodes": {"a": {"name": "a", "sub_tasks": ["a"]}}, "sub_tasks": ["a"]},
     "contains itself"),
    ({"name": "x", "control_type": "fallback", "sub_tasks": [{"type": "sleep_action",
                                                              "wait_time": 1}]}, "exactly 2"),
    ({"name": "x", "blackboard": {"bad key": 1}, "sub_tasks": [
        {"type": "sleep_action", "wait_time": 1}]}, "blackboard key"),
    ({"name": "x", "control_type": "dance", "sub_tasks": []}, "unknown control type"),
    ({"name": "x", "sub_tasks": [{"type": "nav_action", "x": 1}]}, "x and y"),
])
def test_bad_trees_are_refused_and_nothing_is_made(runtime: RobotRuntime, tree: dict,
                                                   match: str) -> None:
    with pytest.raises(InvalidRequest, match=match):
        runtime.tasks.create(tree)
    assert runtime.tasks.list() == []


def test_starting_a_running_task_is_refused(runtime: RobotRuntime) -> None:
    task = runtime.tasks.create({"name": "w", "sub_tasks": [{"type": "wait_req_action"}]},
                                start=True)
    with pytest.raises(Conflict, match="already"):
        runtime.tasks.start(task["id"])
    with pytest.raises(NotFound):
        runtime.tasks.start("no-such-task")
    assert runtime.tasks.get(task["id"])["state"] == "WORKING"
