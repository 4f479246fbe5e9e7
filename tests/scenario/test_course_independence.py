"""A drive does not depend on what was driven before it in the same process (issue 31).

``polynav bench clutter`` drives course after course in one process, and its figures are only
worth anything if a course ends as it would driven alone. Anything that outlived a drive at
module level (a cache keyed by shape, footprint or resolution, a planner's scratch buffers
shared between stacks, a profile or config changed by a run and not restored) would break that,
and would as well make a real robot's second goal depend on its first. So each test drives a
course, then others (another body, another kind of course, with and without a map), then the
first course again in a fresh stack, and asks for the same drive to the bit: the same true
poses and the same commands at every control period.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest

from polynav.robot.profile import RobotProfile, load_profile
from polynav.runtime.sim_driver import simulate, simulate_mapless
from polynav.worlds.clutter import ClutterSpec, draw

DRIVE = 12.0  # [s of simulated time] per drive: past the first plans, re-plans and blocks


def _drive(profile: RobotProfile, kind: str, density: float, seed: int, *,
           mapless: bool) -> npt.NDArray[np.float64]:
    """Drive the course of ``kind``, ``density`` and ``seed`` for ``DRIVE`` s in a new stack;
    per control period the true pose, the command and the navigation state's ordinal."""
    course = draw(profile.footprint, ClutterSpec(kind=kind, density=density), seed)
    run = simulate_mapless if mapless else simulate
    driver = run(course.world, seed=seed, people=False, profile=profile)
    driver.run(0.5)
    began = driver.now
    driver.stack.go_to(driver.to_stack_frame(course.goal), driver.now)
    navigator = driver.stack.navigator
    states = list(type(navigator.state))
    rows: list[tuple[float, ...]] = []
    period = 1.0 / driver.stack.config.control_rate
    next_row = driver.now
    while driver.now - began < DRIVE and not navigator.state.finished:
        driver.step()
        if driver.now >= next_row - 1e-9:
            pose, command = driver.sim.true_pose, driver.stack.command
            rows.append((pose.x, pose.y, pose.theta, command.linear, command.angular,
                         float(states.index(navigator.state))))
            next_row += period
    return np.array(rows)


@pytest.mark.parametrize(("robot", "mapless"), [("demo", True), ("research-base", False)])
def test_a_course_drives_the_same_after_other_courses_in_the_same_process(
    robot: str, mapless: bool
) -> None:
    profile = load_profile(robot)
    # A dense lattice course (the benchmark's course 78 for the demo robot without a map).
    first = _drive(profile, "lattice", 0.79, 78, mapless=mapless)
    assert first.shape[0] > 100 and np.abs(first[:, 3]).max() > 0.1  # it drove
    # Others in between: another body and another kind, the other frame, a sparser course.
    other = load_profile("research-base" if robot == "demo" else "delivery")
    _drive(other, "posts", 0.5, 7, mapless=not mapless)
    _drive(profile, "lattice", 0.3, 12, mapless=mapless)
    again = _drive(profile, "lattice", 0.79, 78, mapless=mapless)
    assert again.shape == first.shape
    np.testing.assert_array_equal(again, first)
