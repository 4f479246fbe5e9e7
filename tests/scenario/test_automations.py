"""Automation programs on the simulated robot: a separate process, limited, reaching the robot
only through actions. The loop thread runs (at high speed) because the program's requests are
served while the robot moves."""

from __future__ import annotations

import math
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from polynav.automation.runner import AutomationLimits
from polynav.errors import Conflict
from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds.world import World


def _config(**limits: float) -> RuntimeConfig:
    return RuntimeConfig(people=False, speed=20.0, automations=True,
                         automation_limits=AutomationLimits(**limits))  # type: ignore[arg-type]


@pytest.fixture
def data(tmp_path: Path) -> Path:
    return tmp_path / "data"


def _runtime(world: World, data: Path, config: RuntimeConfig) -> Iterator[RobotRuntime]:
    with SiteStore.open(data, seed_world=world) as store:
        rt = RobotRuntime.simulated(store, world, config=config)
        rt.start_navigation("floor1")
        rt.advance(0.5)
        rt.start()
        try:
            yield rt
        finally:
            rt.stop()


@pytest.fixture
def runtime(world: World, data: Path) -> Iterator[RobotRuntime]:
    yield from _runtime(world, data, _config(wall_seconds=60.0, cpu_seconds=5))


def _wait(rt: RobotRuntime, run_id: str, timeout: float = 60.0) -> dict:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        run = rt.automations.runner.run(run_id)
        if run["state"] != "WORKING":
            return run
        time.sleep(0.05)
    raise AssertionError(f"run still working: {rt.automations.runner.run(run_id)}")


def test_a_program_drives_the_robot_through_actions(runtime: RobotRuntime) -> None:
    program = (
        "r = robot.go(point='lobby')\n"
        "print('arrived', r['state'])\n"
        "robot.say('at x %.1f' % r['blackboard']['nav.x'])\n"
        "open('notes.txt', 'w').write('done')\n"
    )
    run = _wait(runtime, runtime.automations.runner.start("a1", program)["id"])
    assert run["state"] == "COMPLETE", run
    assert "arrived COMPLETE" in run["log"]
    assert run["actions"] == 2
    truth = runtime.simulation.true_pose
    assert math.hypot(truth.x - 5.5, truth.y - 12.5) < 0.1
    assert runtime.peripherals.devices.speaker.text == "at x 5.5"


def test_a_program_that_loops_for_ever_is_killed_at_its_cpu_limit(world: World,
                                                                  data: Path) -> None:
    for rt in _runtime(world, data, _config(wall_seconds=30.0, cpu_seconds=1)):
        run = _wait(rt, rt.automations.runner.start("spin", "while True:\n    pass\n")["id"])
        assert run["state"] == "ERROR" and "CPU time limit" in run["reason"]


def test_a_program_that_waits_for_ever_is_killed_at_its_wall_limit(world: World,
                                                                   data: Path) -> None:
    for rt in _runtime(world, data, _config(wall_seconds=1.0, cpu_seconds=5)):
        run = _wait(rt, rt.automations.runner.start("nap", "import time\ntime.sleep(3600)\n")["id"])
        assert run["state"] == "ERROR" and "wall time limit" in run["reason"]


@pytest.mark.parametrize(("program", "message"), [
    ("import polynav\n", "may not import polynav"),
    ("from polynav.runtime import robot_runtime\n", "may not import polynav"),
    ("open('/tmp/outside-polynav-automation.txt', 'w').write('x')\n", "only in its folder"),
    ("open('../escape.txt', 'w').write('x')\n", "only in its folder"),
    ("import os\nos.remove('/etc/hostname')\n", "only in its folder"),
    ("import subprocess\nsubprocess.run(['true'])\n", "may not use"),
    ("import socket\nsocket.create_connection(('127.0.0.1', 1))\n", "may not use"),
    ("import numpy\n", "No module named"),
])
def test_a_program_that_reaches_outside_fails(runtime: RobotRuntime, data: Path,
                                              program: str, message: str) -> None:
    run = _wait(runtime, runtime.automations.runner.start("bad", program)["id"])
    assert run["state"] == "ERROR" and message in run["reason"], run
    assert not Path("/tmp/outside-polynav-automation.txt").exists()
    assert not (data / "automations" / "escape.txt").exists()


def test_a_bad_action_is_an_error_the_program_can_catch(runtime: RobotRuntime) -> None:
    program = (
        "try:\n"
        "    robot.run('fly_action')\n"
        "except RobotError as exc:\n"
        "    print('refused:', exc)\n"
    )
    run = _wait(runtime, runtime.automations.runner.start("c", program)["id"])
    assert run["state"] == "COMPLETE"
    assert any("unknown action type" in line for line in run["log"])


def test_automations_are_off_by_default(world: World, data: Path) -> None:
    for rt in _runtime(world, data, RuntimeConfig(people=False, speed=20.0)):
        with pytest.raises(Conflict, match="off"):
            rt.automations.runner.start("a", "pass\n")
