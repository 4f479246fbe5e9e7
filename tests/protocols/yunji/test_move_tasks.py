"""Move tasks over a real TCP socket: cruises, retries and trapped notices, charging pile leave
and dock, and the per-move options, against a real runtime on the demo site.

Simulated time advances only when a test calls ``runtime.advance`` (see conftest). Obstacles the
map does not know are put into the simulator's ground truth, as a trolley left in a corridor.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from polynav.geometry import Pose2D, angle_diff
from polynav.maps.keepout import CircleZone
from tests.protocols.yunji.conftest import Client, Harness

TIMEOUT = 300.0  # simulated seconds


def _status(client: Client) -> dict[str, Any]:
    reply = client.request("/api/robot_status")
    assert reply["status"] == "OK", reply
    results = reply["results"]
    assert isinstance(results, dict)
    return results


def _ok(client: Client, command: str) -> dict[str, Any]:
    reply = client.request(command)
    assert reply["status"] == "OK", reply
    return reply


def _wait(h: Harness, client: Client, step: float = 0.5) -> list[dict[str, Any]]:
    """Advance ``step`` s at a time polling robot_status until the move task is not running;
    returns every status seen."""
    seen = []
    for _ in range(int(TIMEOUT / step)):
        h.runtime.advance(step)
        status = _status(client)
        seen.append(status)
        if status["move_status"] != "running":
            return seen
    raise AssertionError("the move task did not end")


def _codes_until(client: Client, last: str) -> list[tuple[str, dict[str, Any]]]:
    """Notifications (code, data) up to and including the first ``last``."""
    out = []
    while True:
        packet = client.push("notification")
        out.append((packet["code"], packet["data"]))
        if packet["code"] == last:
            return out


def _all_invalid(client: Client, cases: dict[str, str]) -> None:
    """Each command is INVALID_REQUEST with a message naming its field."""
    for command, field in cases.items():
        reply = client.request(command)
        assert reply["status"] == "INVALID_REQUEST", (command, reply)
        assert reply["error_message"].startswith(f"{field}: "), reply


# The lobby gate lies on the way from floor 1's start to its corridor: passing it sends
# 01030/01031 between a move's notices (test_door_notices); these tests look at the others.
DOOR_CODES = ("01030", "01031", "01032")


def _codes(notes: list[tuple[str, dict[str, Any]]]) -> list[str]:
    return [code for code, _ in notes if code not in DOOR_CODES]


# -- cruise ------------------------------------------------------------------------------------


def test_a_cruise_over_three_markers_twice_sends_01101_each_leg_then_01102(
    harness: Harness, client: Client
) -> None:
    reply = _ok(client, "/api/move?markers=lobby,front_desk,corridor_west&count=2&uuid=c1")
    assert (reply["command"], reply["uuid"]) == ("/api/move", "c1")
    assert len(reply["task_id"]) == 32 and int(reply["task_id"], 16) >= 1 << 127
    targets = set()
    for status in _wait(harness, client):
        if status["move_status"] == "running":
            assert status["running_status"] == "running"
            targets.add(status["move_target"])
    assert targets == {"lobby", "front_desk", "corridor_west"}
    assert _status(client)["move_status"] == "succeeded"
    notes = _codes_until(client, "01102")
    cruise = {
        "markers": ["lobby", "front_desk", "corridor_west"], "count": 2, "distance_tolerance": 0.5
    }
    legs = ["lobby", "front_desk", "corridor_west"] * 2
    assert notes[0] == ("01101", cruise)
    assert [(code, data.get("target")) for code, data in notes[1:-1]
            if code not in DOOR_CODES] == [
        pair for leg in legs for pair in (("01001", leg), ("01002", leg))
    ]
    assert notes[-1] == ("01102", cruise)


def test_a_cruise_whose_last_leg_fails_sends_01103(harness: Harness, client: Client) -> None:
    _ok(client, "/api/markers/insert_by_pose?name=in_wall&x=10.0&y=8.5&theta=0")
    _ok(client, "/api/move?markers=in_wall,lobby,in_wall&distance_tolerance=1.0")
    _wait(harness, client)
    assert _status(client)["move_status"] == "failed"
    notes = _codes_until(client, "01103")
    assert [c for c in _codes(notes) if c not in ("01203", "01007")] == [
        "01101", "01001", "01003", "01001", "01002", "01001", "01003", "01103"
    ]
    assert notes[-1][1]["distance_tolerance"] == 1.0


def test_move_cancel_ends_a_cruise_with_01104(harness: Harness, client: Client) -> None:
    _ok(client, "/api/move?markers=lobby,front_desk&count=-1")
    harness.runtime.advance(5.0)
    assert _status(client)["move_status"] == "running"
    assert client.request("/api/move?marker=lobby")["status"] == "REQUEST_DENIED"
    _ok(client, "/api/move/cancel")
    assert _status(client)["move_status"] == "canceled"
    notes = _codes_until(client, "01104")
    assert _codes(notes) == ["01101", "01001", "01004", "01104"]
    assert notes[-1][1]["count"] == -1


def test_cruise_bad_requests_are_invalid(harness: Harness, client: Client) -> None:
    cases = {
        "/api/move?markers=lobby": "markers",
        "/api/move?markers=lobby,": "markers",
        "/api/move?markers=lobby,front_desk&count=0": "count",
        "/api/move?markers=lobby,front_desk&count=-2": "count",
        "/api/move?markers=lobby,front_desk&count=x": "count",
        "/api/move?markers=lobby,front_desk&distance_tolerance=0.3": "distance_tolerance",
        "/api/move?markers=lobby,front_desk&max_continuous_retries=-1": "max_continuous_retries",
    }
    _all_invalid(client, cases)
    reply = client.request("/api/move?markers=lobby,nowhere")
    assert (reply["status"], reply["error_message"]) == ("INVALID_REQUEST", "Marker Not Found")
    assert _status(client)["move_status"] == "idle"  # nothing started


# -- retries, trapped, planning ---------------------------------------------------------------


def test_an_obstacle_across_the_way_sends_01204_01005_then_01006_and_01003(
    harness: Harness, client: Client
) -> None:
    _ok(client, "/api/move?marker=corridor_west&max_continuous_retries=2")
    harness.runtime.advance(2.0)
    harness.runtime.simulation.place_obstacle("floor1", 11.0, 12.4, 0.8)
    statuses = _wait(harness, client)
    assert statuses[-1]["move_status"] == "failed"
    retries = [s["move_retry_times"] for s in statuses]
    assert retries == sorted(retries) and retries[-1] >= 3  # +1 per re-plan after a failure
    codes = _codes(_codes_until(client, "01003"))
    # Blocked (01204), wait, re-plan (01005) ... until 3 retries in a row got nowhere.
    assert codes[:3] == ["01001", "01204", "01005"]
    assert codes[-3:] == ["01204", "01006", "01003"]
    assert codes.count("01005") == retries[-1] - 1
    # The obstacle's marks and inflation may close the corridor for one plan (01203, planning
    # failed), then the marks are cleared and the next plan goes on; nothing else is sent.
    assert {"01001", "01204", "01005", "01006", "01003"} <= set(codes)
    assert set(codes) <= {"01001", "01204", "01005", "01006", "01003", "01203"}


def test_a_location_in_a_wall_sends_01007_then_01003_without_retries(
    harness: Harness, client: Client
) -> None:
    _ok(client, "/api/move?location=10.0,8.5,0")
    statuses = _wait(harness, client)
    assert statuses[-1]["move_status"] == "failed"
    notes = _codes_until(client, "01003")
    assert _codes(notes) == ["01001", "01203", "01007", "01003"]
    level = client.request("/api/robot_status")  # still answering
    assert level["status"] == "OK"
    assert all(data == {"target": ""} for code, data in notes if code in ("01001", "01007"))


def test_standing_in_a_forbidden_zone_sends_01202_and_01203_every_5_s(
    harness: Harness, client: Client
) -> None:
    runtime = harness.runtime
    runtime.store.set_keepouts("floor1", [CircleZone(8.0, 8.5, 0.4)])
    _ok(client, "/api/map/set_current_map?map_name=floor1&floor=1")
    runtime.advance(0.5)
    _ok(client, "/api/move?marker=lobby")
    statuses = _wait(harness, client)
    assert statuses[-1]["move_status"] == "failed"
    codes = _codes(_codes_until(client, "01003"))
    assert codes[:3] == ["01001", "01202", "01203"]
    seconds = len(statuses) * 0.5
    assert codes.count("01202") == codes.count("01203") <= seconds / 5.0 + 1


def test_a_robot_carried_off_its_pose_sends_02010_robot_maybe_lost(
    harness: Harness, client: Client
) -> None:
    harness.runtime.simulation.teleport("floor1", Pose2D(30.0, 12.4, 2.0))
    for _ in range(40):
        harness.runtime.advance(0.5)
        if harness.runtime.status().localization_state == "lost":
            break
    note = client.push("notification")
    while note["code"] != "02010":
        note = client.push("notification")
    assert (note["level"], note["description"], note["data"]) == (
        "warning", "The robot maybe lost.", {})


# -- charging pile ----------------------------------------------------------------------------


def _dock(h: Harness, client: Client) -> list[dict[str, Any]]:
    _ok(client, "/api/move?marker=charger")
    statuses = _wait(h, client, step=0.25)
    h.runtime.advance(0.5)
    return statuses


def test_a_move_to_the_charging_pile_docks_and_charging_starts(
    harness: Harness, client: Client
) -> None:
    statuses = _dock(harness, client)
    assert "dock_to_charging_pile" in {s["running_status"] for s in statuses}
    status = _status(client)
    assert (status["move_status"], status["charge_state"], status["chargepile_id"]) == (
        "succeeded", True, "2")
    notes = _codes_until(client, "02001")
    assert _codes(notes) == ["01001", "01020", "01021", "01002", "02001"]
    assert all(data.get("target") == "charger" for code, data in notes if code != "02001")


def test_a_move_from_the_charging_pile_leaves_it_first(harness: Harness, client: Client) -> None:
    _dock(harness, client)
    _codes_until(client, "02001")
    _ok(client, "/api/move?marker=lobby")
    statuses = _wait(harness, client, step=0.25)
    assert statuses[0]["running_status"] == "leave_charging_pile"
    assert statuses[-1]["move_status"] == "succeeded"
    assert not statuses[-1]["charge_state"]
    assert _codes(_codes_until(client, "01002")) == ["01001", "01010", "02002", "01011", "01002"]


def test_leaving_the_pile_under_estop_retries_01013_then_fails_01012(
    harness: Harness, client: Client
) -> None:
    _dock(harness, client)
    _codes_until(client, "02001")
    _ok(client, "/api/estop?flag=true")
    _ok(client, "/api/move?marker=lobby")
    statuses = _wait(harness, client)
    assert statuses[-1]["move_status"] == "failed"
    notes = _codes_until(client, "01003")
    assert _codes(notes) == ["02003", "01001", "01010", "01013", "01013", "01013", "01012", "01003"]
    assert all(data == {"target": "lobby"} for code, data in notes if code in ("01012", "01013"))


def test_docking_where_no_pile_stands_sends_01022_and_01024(
    harness: Harness, client: Client
) -> None:
    _ok(client, "/api/markers/insert_by_pose?name=dead_pile&x=5.5&y=12.5&theta=3.14&type=11")
    _ok(client, "/api/move?marker=dead_pile")
    statuses = _wait(harness, client)
    assert statuses[-1]["move_status"] == "failed"
    notes = _codes_until(client, "01003")
    assert _codes(notes) == ["01001", "01020", "01022", "01024", "01003"]
    assert notes[2][1] == notes[3][1] == {"target": "dead_pile"}
    assert not _status(client)["charge_state"]


def test_docking_held_too_long_times_out_with_01027(harness: Harness, client: Client) -> None:
    _ok(client, "/api/move?marker=charger")
    for _ in range(int(TIMEOUT / 0.25)):
        harness.runtime.advance(0.25)
        if _status(client)["running_status"] == "dock_to_charging_pile":
            break
    _ok(client, "/api/estop?flag=true")
    statuses = _wait(harness, client)
    assert statuses[-1]["move_status"] == "failed"
    notes = _codes_until(client, "01003")
    assert [c for c in _codes(notes) if c != "02003"] == [
        "01001", "01020", "01022", "01027", "01003"
    ]


# -- per-move options --------------------------------------------------------------------------


def test_move_options_reverse_heading_theta_and_distance_tolerance(
    harness: Harness, client: Client
) -> None:
    runtime = harness.runtime
    _ok(client, "/api/move?location=5.5,12.5,3.14159&yaw_goal_reverse_allowed=1")
    _wait(harness, client)
    theta = runtime.simulation.true_pose.theta
    assert min(abs(angle_diff(theta, 0.0)), abs(angle_diff(theta, math.pi))) <= 0.1
    _ok(client, "/api/move?location=8.0,8.5,0&theta_tolerance=0.6")
    assert _wait(harness, client)[-1]["move_status"] == "succeeded"
    assert abs(angle_diff(runtime.simulation.true_pose.theta, 0.0)) <= 0.6
    # A location inside the west wall: refused as unreachable, then within 1 m it succeeds.
    _ok(client, "/api/move?location=0.2,12.5,3.14159")
    assert _wait(harness, client)[-1]["move_status"] == "failed"
    _ok(client, "/api/move?location=0.2,12.5,3.14159&distance_tolerance=1.0")
    assert _wait(harness, client)[-1]["move_status"] == "succeeded"
    end = runtime.simulation.true_pose
    assert float(np.hypot(end.x - 0.2, end.y - 12.5)) <= 1.0


def test_bad_move_options_are_invalid(harness: Harness, client: Client) -> None:
    cases = {
        "/api/move?marker=lobby&theta_tolerance=0": "theta_tolerance",
        "/api/move?marker=lobby&distance_tolerance=-1": "distance_tolerance",
        "/api/move?marker=lobby&occupied_tolerance=0.05": "occupied_tolerance",
        "/api/move?marker=lobby&max_continuous_retries=1.5": "max_continuous_retries",
        "/api/move?marker=lobby&yaw_goal_reverse_allowed=yes": "yaw_goal_reverse_allowed",
    }
    _all_invalid(client, cases)


COVERED: dict[str, str] = {
    "cmd 1.2 /api/move": "test_a_cruise_over_three_markers_twice_sends_01101_each_leg_then_01102",
    "notify 10 01101": "test_a_cruise_over_three_markers_twice_sends_01101_each_leg_then_01102",
    "notify 10 01102": "test_a_cruise_over_three_markers_twice_sends_01101_each_leg_then_01102",
    "notify 10 01103": "test_a_cruise_whose_last_leg_fails_sends_01103",
    "notify 10 01104": "test_move_cancel_ends_a_cruise_with_01104",
    "notify 10 01005": "test_an_obstacle_across_the_way_sends_01204_01005_then_01006_and_01003",
    "notify 10 01006": "test_an_obstacle_across_the_way_sends_01204_01005_then_01006_and_01003",
    "notify 10 01204": "test_an_obstacle_across_the_way_sends_01204_01005_then_01006_and_01003",
    "notify 10 01007": "test_a_location_in_a_wall_sends_01007_then_01003_without_retries",
    "notify 10 01203": "test_standing_in_a_forbidden_zone_sends_01202_and_01203_every_5_s",
    "notify 10 01202": "test_standing_in_a_forbidden_zone_sends_01202_and_01203_every_5_s",
    "notify 10 02010": "test_a_robot_carried_off_its_pose_sends_02010_robot_maybe_lost",
    "notify 10 01020": "test_a_move_to_the_charging_pile_docks_and_charging_starts",
    "notify 10 01021": "test_a_move_to_the_charging_pile_docks_and_charging_starts",
    "notify 10 02001": "test_a_move_to_the_charging_pile_docks_and_charging_starts",
    "notify 10 01010": "test_a_move_from_the_charging_pile_leaves_it_first",
    "notify 10 01011": "test_a_move_from_the_charging_pile_leaves_it_first",
    "notify 10 02002": "test_a_move_from_the_charging_pile_leaves_it_first",
    "notify 10 01012": "test_leaving_the_pile_under_estop_retries_01013_then_fails_01012",
    "notify 10 01013": "test_leaving_the_pile_under_estop_retries_01013_then_fails_01012",
    "notify 10 01022": "test_docking_where_no_pile_stands_sends_01022_and_01024",
    "notify 10 01024": "test_docking_where_no_pile_stands_sends_01022_and_01024",
    "notify 10 01027": "test_docking_held_too_long_times_out_with_01027",
}
