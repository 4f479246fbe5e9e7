"""Whole missions with robots described by profiles, on simulated time.

A profile's speed is honoured end to end: the planner plans for its body, the controller never
commands more than its limit and the simulator never drives faster, yet on a long straight the
robot gets close to it. A rectangular base crosses a room on its polygon body without touching.
"""

from __future__ import annotations

import math
from dataclasses import replace

import pytest

from polynav.geometry import Pose2D
from polynav.nav.attempt import NavigationState
from polynav.robot.profile import Cruise, Limits, RobotProfile, load_profile
from polynav.runtime.sim_driver import SimDriver, simulate
from tests.unit.robot.sim.ascii_world import ascii_world

# A corridor 30 m long and 3 m wide.
CORRIDOR = ascii_world(
    "\n".join(["#" * 300] + ["#" + "." * 298 + "#"] * 30 + ["#" * 300]),
    resolution=0.1,
    start=Pose2D(1.5, 1.6, 0.0),
)


def _profile_at(speed: float) -> RobotProfile:
    demo = load_profile("demo")
    return replace(
        demo,
        name=f"demo-{speed:g}",
        limits=replace(Limits(), max_linear_velocity=speed),
        cruise=replace(Cruise(), linear_velocity=speed, linear_acceleration=1.0,
                       linear_deceleration=2.0),
    )


def _drive(driver: SimDriver, goal: Pose2D, timeout: float) -> tuple[float, float]:
    """Run to ``goal``; returns the top true speed [m/s] and the top commanded one."""
    driver.stack.go_to(goal, driver.now)
    top_true = top_command = 0.0
    end = driver.now + timeout
    while not driver.stack.navigator.state.finished and driver.now < end:
        before = driver.sim.true_pose
        t0 = driver.now
        driver.step()
        dt = driver.now - t0
        top_true = max(top_true, driver.sim.true_pose.distance_to(before) / dt)
        top_command = max(top_command, abs(driver.stack.command.linear))
    return top_true, top_command


def test_a_15_mps_profile_is_honoured_by_planner_controller_and_simulator() -> None:
    profile = _profile_at(1.5)
    driver = simulate(CORRIDOR, seed=3, people=False, profile=profile)
    assert driver.stack.config.controller.max_linear_velocity == 1.5
    assert driver.sim.config.max_linear_velocity == 1.5
    goal = Pose2D(27.0, 1.6, 0.0)
    top_true, top_command = _drive(driver, goal, timeout=60.0)
    attempt = driver.stack.navigator.attempt
    assert attempt is not None and attempt.state is NavigationState.SUCCEEDED
    assert driver.sim.true_pose.distance_to(goal) <= 0.1
    assert driver.sim.collisions == []
    assert top_command <= 1.5 + 1e-9
    assert top_true <= 1.5 + 1e-6
    assert top_true >= 1.4  # the long straight lets it reach close to its limit


def test_the_same_robot_capped_lower_by_its_profile_drives_slower() -> None:
    driver = simulate(CORRIDOR, seed=3, people=False, profile=_profile_at(0.8))
    top_true, _ = _drive(driver, Pose2D(27.0, 1.6, 0.0), timeout=80.0)
    assert 0.7 <= top_true <= 0.8 + 1e-6


@pytest.mark.parametrize("name", ["research-base", "delivery"])
def test_builtin_profiles_cross_a_room(name: str) -> None:
    room = ascii_world(
        "\n".join(["#" * 120] + ["#" + "." * 118 + "#"] * 60 + ["#" * 120]),
        resolution=0.1, start=Pose2D(1.0, 1.0, 0.0),
    )
    driver = simulate(room, seed=2, people=False, profile=load_profile(name))
    goal = Pose2D(10.5, 4.5, math.pi / 2)
    _drive(driver, goal, timeout=60.0)
    attempt = driver.stack.navigator.attempt
    assert attempt is not None and attempt.state is NavigationState.SUCCEEDED, attempt
    assert driver.sim.true_pose.distance_to(goal) <= 0.1
    assert driver.sim.collisions == []
