"""A move to a marker on another floor over the real socket: the robot rides lift_1, the 040xx
notifications come in the documented order (§3.10.4 L1034-L1040), ``running_status`` walks the
lift states, ``lift_status`` answers during the ride, and the move ends on the marker."""

from __future__ import annotations

import math
from typing import Any

from tests.protocols.yunji.conftest import Client, Harness

TIMEOUT = 400.0  # simulated seconds
LIFT_STATES = ["goto_lift", "wait_lift_unlock", "wait_lift_outside", "enter_lift", "take_lift",
               "exit_lift"]


def _ok(client: Client, command: str) -> dict[str, Any]:
    reply = client.request(command)
    assert reply["status"] == "OK", reply
    return reply


def test_move_to_a_floor_3_marker_rides_the_lift_with_its_notifications(
    harness: Harness, client: Client
) -> None:
    plan = _ok(client, "/api/make_plan?start_x=8.0&start_y=8.5&start_floor=1"
                       "&goal_x=11.5&goal_y=18.0&goal_floor=3")
    assert plan["results"]["distance"] > 50.0
    assert client.request("/api/lift_status")["status"] == "UNKNOWN_ERROR"  # no ride yet
    _ok(client, "/api/move?marker=room_301")
    states: list[str] = []
    lift_floors: list[int] = []
    for _ in range(int(TIMEOUT / 0.5)):
        harness.runtime.advance(0.5)
        status = _ok(client, "/api/robot_status")["results"]
        if status["move_status"] != "running":
            break
        if not states or states[-1] != status["running_status"]:
            states.append(status["running_status"])
        if status["running_status"] in ("take_lift", "exit_lift"):
            lift_floors.append(_ok(client, "/api/lift_status")["results"]["current_floor"])
    assert status["move_status"] == "succeeded", status
    assert [s for s in states if s in LIFT_STATES] == [
        s for s in LIFT_STATES if s in states]
    assert {"goto_lift", "wait_lift_outside", "enter_lift", "take_lift", "exit_lift"} <= set(
        states)
    assert lift_floors[0] in (1, 2) and lift_floors[-1] == 3
    codes = []
    while True:
        packet = client.push("notification")
        codes.append(packet["code"])
        if packet["code"] in ("01002", "01003"):
            break
    lift = [c for c in codes if c.startswith("040")]
    assert codes[0] == "01001" and codes[-1] == "01002"
    assert lift == ["04000", "04001", "04010", "04011", "04030", "04031", "04020", "04021",
                    "04050", "04051"]
    final = _ok(client, "/api/robot_status")["results"]
    pose = harness.runtime.simulation.true_pose
    goal = harness.runtime.store.point("floor3", "room_301").pose
    assert harness.runtime.simulation.floor == "floor3" and final["current_floor"] == 3
    assert math.hypot(pose.x - goal.x, pose.y - goal.y) <= 0.05
    assert abs(math.remainder(pose.theta - goal.theta, math.tau)) <= 0.1


def test_make_plan_across_floors_without_a_lift_cannot_be_reached(
    harness: Harness, client: Client
) -> None:
    harness.runtime.store.set_connections([])  # type: ignore[attr-defined]
    reply = client.request("/api/make_plan?start_x=8.0&start_y=8.5&start_floor=1"
                           "&goal_x=11.5&goal_y=18.0&goal_floor=3")
    assert (reply["status"], reply["error_message"]) == (
        "GOAL_CAN_NOT_BE_REACHED", "goal can not be reached")
    assert client.request("/api/move?marker=room_301")["status"] == "REQUEST_DENIED"


COVERED: dict[str, str] = {
    f"notify 10 {code}": "test_move_to_a_floor_3_marker_rides_the_lift_with_its_notifications"
    for code in ("04000", "04001", "04010", "04011", "04030", "04031", "04020", "04021",
                 "04050", "04051")
}
