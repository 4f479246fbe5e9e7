"""Site and navigation queries over a real TCP socket: accessible points, distance probes,
path lengths, the planned path, lift status and the human_detection stream.

Simulated time advances only when a test calls ``runtime.advance`` (see conftest).
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

import pytest

from polynav.geometry import Pose2D
from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds.world import World
from tests.protocols.yunji.conftest import Client, Harness, serving


def _ok(client: Client, command: str) -> Any:
    reply = client.request(command)
    assert (reply["command"], reply["status"], reply["error_message"]) == (
        command.split("?")[0], "OK", ""), reply
    return reply["results"]


def _invalid(client: Client, command: str, field: str) -> None:
    reply = client.request(command)
    assert reply["status"] == "INVALID_REQUEST", (command, reply)
    assert reply["error_message"].startswith(f"{field}: "), (command, reply)


# -- accessible_point_query --------------------------------------------------------------------


def test_accessible_point_query_returns_a_free_point_itself_and_moves_a_wall_point_out(
    harness: Harness, client: Client
) -> None:
    assert _ok(client, "/api/map/accessible_point_query?x=8.0&y=8.5") == {
        "position": {"x": 8.0, "y": 8.5}}
    # (10.0, 8.5) lies in a wall: the answer is the nearest place the robot fits and reaches.
    found = _ok(client, "/api/map/accessible_point_query?x=10.0&y=8.5")["position"]
    distance = math.hypot(found["x"] - 10.0, found["y"] - 8.5)
    assert 0.2 < distance < 1.0, found
    costmap = harness.runtime.navigation_stack
    assert costmap is not None and costmap.costmap.cost_at(found["x"], found["y"]) < 253
    # A room the robot cannot reach (outside the building, beyond the map's west edge).
    reply = client.request("/api/map/accessible_point_query?x=-30&y=8.5")
    assert reply["status"] == "GOAL_CAN_NOT_BE_REACHED", reply
    _invalid(client, "/api/map/accessible_point_query?x=8.0", "y")
    _invalid(client, "/api/map/accessible_point_query?x=abc&y=1", "x")


# -- distance_probe ----------------------------------------------------------------------------


def test_distance_probe_measures_to_the_scan_and_to_the_static_map(
    harness: Harness, client: Client
) -> None:
    results = _ok(client, "/api/map/distance_probe?x=8.0&y=8.5")
    dist = results["env_dist"]
    assert 0.3 < dist["static"] < 3.0 and 0.3 < dist["obstacle"] < 3.0, dist
    # An obstacle the map does not know, 0.6 m from the probed point: only the lidar sees it.
    harness.runtime.simulation.place_obstacle("floor1", 8.0, 9.5, 0.2)
    harness.runtime.advance(0.5)
    after = _ok(client, "/api/map/distance_probe?x=8.0&y=8.9")["env_dist"]
    assert after["obstacle"] < 0.5 < after["static"], after
    # Beyond the lidar's 12 m: the sensed distance cannot be measured.
    far = _ok(client, "/api/map/distance_probe?x=31.6&y=21.0")["env_dist"]
    assert far["obstacle"] == -1 and far["static"] > 0.0
    _invalid(client, "/api/map/distance_probe?y=1", "x")


# -- make_plan ---------------------------------------------------------------------------------


def test_make_plan_gives_the_path_length_or_goal_can_not_be_reached(client: Client) -> None:
    same = _ok(client, "/api/make_plan?start_x=8.0&start_y=8.5&start_floor=1"
                       "&goal_x=8.0&goal_y=9.5&goal_floor=1")
    assert abs(same["distance"] - 1.0) < 0.05  # a straight metre
    around = _ok(client, "/api/make_plan?start_x=8.0&start_y=8.5&start_floor=1"
                         "&goal_x=31.6&goal_y=21.0&goal_floor=1")
    assert around["distance"] > math.hypot(31.6 - 8.0, 21.0 - 8.5)  # walls in between
    other = _ok(client, "/api/make_plan?start_x=36&start_y=15&start_floor=2"
                        "&goal_x=4&goal_y=11&goal_floor=2")
    assert other["distance"] > 32.0
    # Across floors: the in-map paths of the route through a lift (to its door, from its door).
    across = _ok(client, "/api/make_plan?start_x=8&start_y=8.5&start_floor=1"
                         "&goal_x=4&goal_y=11&goal_floor=2")
    assert across["distance"] > 28.0 + 31.0
    for command in (
        "/api/make_plan?start_x=8&start_y=8.5&start_floor=1&goal_x=10&goal_y=8.5&goal_floor=1",
        "/api/make_plan?start_x=8&start_y=8.5&start_floor=1&goal_x=8.05&goal_y=5&goal_floor=3",
        "/api/make_plan?start_x=8&start_y=8.5&start_floor=1&goal_x=-50&goal_y=8&goal_floor=1",
    ):
        reply = client.request(command)
        assert (reply["status"], reply["error_message"]) == (
            "GOAL_CAN_NOT_BE_REACHED", "goal can not be reached"), (command, reply)
        assert "results" not in reply
    _invalid(client, "/api/make_plan?start_x=8&start_y=8.5&start_floor=7&goal_x=4&goal_y=11"
                     "&goal_floor=1", "floor")
    _invalid(client, "/api/make_plan?start_x=8&start_y=8.5&start_floor=1&goal_x=4&goal_y=11",
             "goal_floor")
    _invalid(client, "/api/make_plan?start_x=8&start_y=8.5&start_floor=x&goal_x=4&goal_y=11"
                     "&goal_floor=1", "start_floor")


# -- get_planned_path --------------------------------------------------------------------------


def test_get_planned_path_is_the_running_plan_or_empty(harness: Harness, client: Client) -> None:
    assert _ok(client, "/api/get_planned_path") == {"path": []}
    assert client.request("/api/move?marker=kitchen")["status"] == "OK"
    harness.runtime.advance(1.0)
    path = _ok(client, "/api/get_planned_path")["path"]
    assert 2 <= len(path) <= 2000
    kitchen = harness.runtime.store.point("floor1", "kitchen").pose
    assert math.hypot(path[-1][0] - kitchen.x, path[-1][1] - kitchen.y) < 0.05
    pose = harness.runtime.status().pose
    assert math.hypot(path[0][0] - pose.x, path[0][1] - pose.y) < 0.5
    assert all(isinstance(v, float) for point in path for v in point)
    assert client.request("/api/move/cancel")["status"] == "OK"
    assert _ok(client, "/api/get_planned_path") == {"path": []}


# -- lift_status -------------------------------------------------------------------------------


def test_lift_status_outside_a_lift_ride_is_the_timeout_error(client: Client) -> None:
    reply = client.request("/api/lift_status?uuid=l1")
    assert (reply["command"], reply["uuid"], reply["status"]) == (
        "/api/lift_status", "l1", "UNKNOWN_ERROR")
    assert reply["error_message"].startswith("timeout")
    assert "results" not in reply


# -- human_detection ---------------------------------------------------------------------------


@pytest.fixture
def with_people(world: World, store: SiteStore) -> Iterator[Harness]:
    runtime = RobotRuntime.simulated(store, world, config=RuntimeConfig(people=True, seed=3))
    with serving(runtime) as h:
        yield h


def test_human_detection_streams_the_people_the_lidar_sees_in_the_robot_frame(
    with_people: Harness,
) -> None:
    harness = with_people
    client = harness.client()
    runtime = harness.runtime
    runtime.set_initial_pose(Pose2D(13.5, 12.4, 0.0))  # the west corridor, facing east
    runtime.advance(0.5)
    reply = client.request("/api/request_data?topic=human_detection&frequency=2")
    assert reply["status"] == "OK"
    seen: list[dict[str, Any]] = []
    for _ in range(60):
        runtime.advance(0.5)
        packet = client.push("callback", "human_detection")
        seen.append(packet["results"])
    assert any(results == {} for results in seen)  # nobody in sight for a while
    tracked = [results for results in seen if results]
    assert tracked, "a walker crosses the corridor in sight of the robot"
    for results in tracked:
        for key, person in results.items():
            assert key.startswith("legtrack ") and key.split(" ")[1].isdigit()
            assert set(person) == {"position", "velocity"}
            x, y = person["position"]["x"], person["position"]["y"]
            assert math.hypot(x, y) <= 12.0  # within the lidar's reach
            assert math.hypot(person["velocity"]["x"], person["velocity"]["y"]) < 2.0
    # Robot frame: a detection at (x, y) is where a walker truly is, seen from the robot.
    for _ in range(60):
        latest = fresh_detection(client)
        if latest:
            break
        runtime.advance(0.5)
    assert latest, "a walker comes in sight again"
    truth = runtime.simulation.people_poses()
    pose = runtime.simulation.true_pose
    for person in latest.values():
        x, y = person["position"]["x"], person["position"]["y"]
        wx = pose.x + math.cos(pose.theta) * x - math.sin(pose.theta) * y
        wy = pose.y + math.sin(pose.theta) * x + math.cos(pose.theta) * y
        assert min(math.hypot(wx - p.x, wy - p.y) for p in truth) < 0.6


def fresh_detection(client: Client) -> dict[str, Any]:
    """The human detection of the world as it stands: the stream may run a packet ahead of the
    reader, so it is stopped, what was on the way forgotten, and started again (its first
    packet is built at once)."""
    off = client.request("/api/request_data?topic=human_detection&switch=off")
    assert off["status"] == "OK"
    client.pushed.clear()
    client.request("/api/request_data?topic=human_detection&frequency=2")
    results: dict[str, Any] = client.push("callback", "human_detection")["results"]
    return results


COVERED: dict[str, str] = {
    "cmd 14.5 /api/map/accessible_point_query":
        "test_accessible_point_query_returns_a_free_point_itself_and_moves_a_wall_point_out",
    "cmd 14.6 /api/map/distance_probe":
        "test_distance_probe_measures_to_the_scan_and_to_the_static_map",
    "cmd 22 /api/make_plan": "test_make_plan_gives_the_path_length_or_goal_can_not_be_reached",
    "cmd 20 /api/get_planned_path": "test_get_planned_path_is_the_running_plan_or_empty",
    "cmd 21 /api/lift_status": "test_lift_status_outside_a_lift_ride_is_the_timeout_error",
    "cmd 9.2 /api/request_data?topic=human_detection":
        "test_human_detection_streams_the_people_the_lidar_sees_in_the_robot_frame",
}
