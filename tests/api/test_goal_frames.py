"""Goal frames over real HTTP around the real runtime (issue 31, item 6): "10 m ahead" means
10 m ahead. The README's mapless example, a goal relative to the robot after it has moved and
turned, the same on a map, and the frame in the status, on the demo world with the research
base. The runtime's loop is not threaded: the test advances simulated time between requests, and
checks the simulator's ground truth, not the robot's own estimate."""

from __future__ import annotations

import math
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest

from polynav.geometry import Pose2D, angle_diff
from polynav.robot.profile import load_profile
from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds import load_world
from tests.api.server import native_client

# README.md, "Your own robot, and no map at all": 10 m ahead of the start, then back 10 m.
README_GOAL = {"x": 10, "y": 0, "theta": 0}
README_RELATIVE_GOAL = {"x": -10, "y": 0, "theta": 0, "frame": "robot"}


@pytest.fixture
def runtime(tmp_path: Path) -> Iterator[RobotRuntime]:
    world = load_world("demo")
    with SiteStore.open(tmp_path / "data", seed_world=world) as store:
        yield RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False, seed=7),
                                     profile=load_profile("research-base"))


@pytest.fixture
def http(runtime: RobotRuntime) -> Iterator[httpx.Client]:
    with native_client(runtime, timeout=30.0) as client:
        yield client


def _arrive(runtime: RobotRuntime, http: httpx.Client, goal: dict[str, Any],
            timeout: float) -> dict[str, Any]:
    """Send ``goal`` and advance until the attempt ends; the final status."""
    sent = http.post("/api/navigation/goal", json=goal)
    assert sent.status_code == 202, sent.text
    runtime.advance_until(lambda: runtime.status().navigation_state != "running", timeout)
    status: dict[str, Any] = http.get("/api/status").json()
    assert status["navigation"]["state"] == "succeeded", status
    return status


def _near(true: Pose2D, expected: Pose2D, *, xy: float = 0.2, heading: float = 0.15) -> bool:
    return (true.distance_to(expected) <= xy
            and abs(angle_diff(true.theta, expected.theta)) <= heading)


def test_readme_mapless_goals_drive_10m_ahead_of_the_start_then_10m_back_from_there(
    runtime: RobotRuntime, http: httpx.Client
) -> None:
    start = runtime.simulation.true_pose
    assert start != Pose2D()  # the demo start is far from the world's origin
    assert http.post("/api/navigation/mapless").status_code == 200
    runtime.advance(0.5)
    status = http.get("/api/status").json()
    assert (status["mode"], status["map"], status["frame"]) == ("navigating", "odom", "odom")
    assert math.hypot(status["pose"]["x"], status["pose"]["y"]) < 0.05  # it starts at zero
    # 10 m ahead is past the lobby's east wall: the robot finds its way round by the corridor.
    # With no map there is no door rule (doors are placed on the map): the lobby's gate stays
    # shut and the way round is longer, so odometry drifts further (0.21 m measured).
    status = _arrive(runtime, http, README_GOAL, timeout=120.0)
    true = runtime.simulation.true_pose
    expected = start.compose(Pose2D(10.0, 0.0, 0.0))
    assert _near(true, expected, xy=0.3), (true, expected)
    assert status["frame"] == "odom" and status["navigation"]["goal"]["x"] == 10.0
    # The README's relative form: 10 m behind where it now stands, the start again.
    here = true
    _arrive(runtime, http, README_RELATIVE_GOAL, timeout=120.0)
    true = runtime.simulation.true_pose
    assert _near(true, here.compose(Pose2D(-10.0, 0.0, 0.0))), (true, here)
    assert _near(true, start, xy=0.3)
    assert runtime.simulation.collisions == []


def test_a_robot_frame_goal_is_relative_to_where_the_robot_stands_after_it_turned(
    runtime: RobotRuntime, http: httpx.Client
) -> None:
    start = runtime.simulation.true_pose
    assert http.post("/api/navigation/mapless").status_code == 200
    runtime.advance(0.5)
    # First 3 m to the left, ending turned a quarter left (odometry frame).
    _arrive(runtime, http, {"x": 0.0, "y": 3.0, "theta": math.pi / 2}, timeout=60.0)
    here = runtime.simulation.true_pose
    assert _near(here, start.compose(Pose2D(0.0, 3.0, math.pi / 2)))
    # Then 5 m to its right, facing that way: east along the corridor in the world.
    offset = Pose2D(0.0, -5.0, -math.pi / 2)
    status = _arrive(runtime, http, {"x": offset.x, "y": offset.y, "theta": offset.theta,
                                     "frame": "robot"}, timeout=60.0)
    true = runtime.simulation.true_pose
    expected = here.compose(offset)
    assert _near(true, expected), (true, expected)
    # The attempt's goal is the converted one, in the odometry frame (about (5, 3, 0)).
    goal = status["navigation"]["goal"]
    assert (goal["x"], goal["y"], goal["theta"]) == pytest.approx((5.0, 3.0, 0.0), abs=0.25)
    assert runtime.simulation.collisions == []


def test_a_robot_frame_goal_on_a_map_is_relative_to_the_estimated_pose(
    runtime: RobotRuntime, http: httpx.Client
) -> None:
    assert http.post("/api/navigation/start", json={"map": "floor1"}).status_code == 200
    runtime.advance(1.0)
    status = http.get("/api/status").json()
    assert (status["map"], status["frame"]) == ("floor1", "map")
    here = runtime.simulation.true_pose
    offset = Pose2D(0.0, 2.5, math.pi / 2)
    status = _arrive(runtime, http, {"x": 0.0, "y": 2.5, "theta": math.pi / 2,
                                     "frame": "robot"}, timeout=60.0)
    assert _near(runtime.simulation.true_pose, here.compose(offset))
    goal = status["navigation"]["goal"]  # on the map: the world's frame in the simulator
    assert (goal["x"], goal["y"]) == pytest.approx((here.x, here.y + 2.5), abs=0.1)
    # The odometry frame is not the frame goals are in on a map.
    wrong = http.post("/api/navigation/goal", json={"x": 1.0, "y": 0.0, "frame": "odom"})
    assert wrong.status_code == 409 and "'map'" in wrong.json()["error"]["message"]


@pytest.mark.parametrize(
    "body",
    [
        {"x": 10, "y": 0, "theta": 0, "frame": "base_link"},
        {"x": 10, "y": 0, "theta": 0, "frame": 3},
        {"x": "ten", "y": 0, "theta": 0},
        {"x": "10", "y": 0, "theta": 0, "frame": "robot"},
        {"point": "lobby", "frame": "robot"},
    ],
)
def test_bad_goal_frames_and_coordinates_are_refused_with_422(
    runtime: RobotRuntime, http: httpx.Client, body: dict[str, Any]
) -> None:
    assert http.post("/api/navigation/mapless").status_code == 200
    r = http.post("/api/navigation/goal", json=body)
    assert r.status_code == 422, r.text
    assert r.json()["error"]["code"] == "validation_error"
    assert runtime.status().navigation_state == "idle"  # nothing started


def test_the_map_frame_while_mapless_is_a_conflict_naming_the_frames(
    runtime: RobotRuntime, http: httpx.Client
) -> None:
    assert http.post("/api/navigation/mapless").status_code == 200
    r = http.post("/api/navigation/goal", json={"x": 1.0, "y": 0.0, "frame": "map"})
    assert r.status_code == 409
    message = r.json()["error"]["message"]
    assert "no map frame" in message and "'odom'" in message and "'robot'" in message
    assert http.post("/api/navigation/goal",
                     json={"x": 1.0, "y": 0.0, "frame": "odom"}).status_code == 202
