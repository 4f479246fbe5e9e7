"""The Yunji server over a real TCP socket, against a real runtime on the demo site.

Simulated time advances only when a test calls ``runtime.advance`` (see conftest).
"""

from __future__ import annotations

import math
from typing import Any

import polynav
from polynav.geometry import angle_diff, quaternion_to_yaw
from tests.protocols.yunji.conftest import Client, Harness

POSITION_TOLERANCE = 0.05
HEADING_TOLERANCE = 0.1
MOVE_TIMEOUT = 120  # simulated seconds


def _status(client: Client) -> dict[str, Any]:
    reply = client.request("/api/robot_status")
    assert reply["status"] == "OK", reply
    results = reply["results"]
    assert isinstance(results, dict)
    return results


def _wait_move(h: Harness, client: Client) -> dict[str, Any]:
    """Advance 0.5 s at a time, polling robot_status as an integrator would, until not running."""
    for _ in range(MOVE_TIMEOUT * 2):
        h.runtime.advance(0.5)
        status = _status(client)
        if status["move_status"] != "running":
            return status
    raise AssertionError("the move did not end")


# -- robot_status / robot_info / version --------------------------------------------------------


def test_robot_status_has_every_field_of_the_spec(client: Client) -> None:
    reply = client.request("/api/robot_status?uuid=abc")
    assert {k: reply[k] for k in ("type", "command", "uuid", "status", "error_message")} == {
        "type": "response", "command": "/api/robot_status", "uuid": "abc", "status": "OK",
        "error_message": "",
    }
    r = reply["results"]
    assert set(r) == {
        "move_target", "move_status", "running_status", "move_retry_times", "charge_state",
        "soft_estop_state", "hard_estop_state", "estop_state", "power_percent", "current_pose",
        "current_floor", "chargepile_id", "error_code",
    }
    assert (r["move_target"], r["move_status"], r["running_status"]) == ("", "idle", "idle")
    assert (r["soft_estop_state"], r["hard_estop_state"], r["estop_state"]) == (
        False, False, False)
    assert (r["current_floor"], r["chargepile_id"], r["error_code"]) == (1, "0", "00000000")
    assert r["move_retry_times"] == 0
    assert r["charge_state"] is False
    assert isinstance(r["power_percent"], int) and 0 <= r["power_percent"] <= 100
    pose = r["current_pose"]
    assert set(pose) == {"x", "y", "theta"}
    assert math.hypot(pose["x"] - 8.0, pose["y"] - 8.5) < 0.1  # the demo's initial point


def test_robot_info_reports_the_product_id(client: Client) -> None:
    reply = client.request("/api/robot_info")
    assert (reply["status"], reply["results"]) == (
        "OK", {"product_id": "WATER-POLYNAV-SIM00001"})


def test_software_get_version_is_polynav_version(client: Client) -> None:
    reply = client.request("/api/software/get_version")
    assert (reply["status"], reply["results"]) == ("OK", polynav.__version__)


# -- move ---------------------------------------------------------------------------------------


def test_move_to_marker_succeeds_within_5_cm_and_0_1_rad(harness: Harness, client: Client) -> None:
    reply = client.request("/api/move?marker=lobby&uuid=7")
    assert (reply["command"], reply["uuid"], reply["status"]) == ("/api/move", "7", "OK")
    assert len(reply["task_id"]) == 32 and int(reply["task_id"], 16) > 0
    running = _status(client)
    assert (running["move_target"], running["move_status"], running["running_status"]) == (
        "lobby", "running", "running")
    final = _wait_move(harness, client)
    assert (final["move_status"], final["running_status"], final["move_target"]) == (
        "succeeded", "idle", "lobby")
    pose = final["current_pose"]
    assert math.hypot(pose["x"] - 5.5, pose["y"] - 12.5) <= POSITION_TOLERANCE
    assert abs(angle_diff(pose["theta"], 0.0)) <= HEADING_TOLERANCE


def test_move_to_location_with_angle_offset_succeeds(harness: Harness, client: Client) -> None:
    reply = client.request("/api/move?location=5.5,12.5,0.0&angle_offset=1.5707963")
    assert reply["status"] == "OK", reply
    final = _wait_move(harness, client)
    assert (final["move_status"], final["move_target"]) == ("succeeded", "")
    pose = final["current_pose"]
    assert math.hypot(pose["x"] - 5.5, pose["y"] - 12.5) <= POSITION_TOLERANCE
    assert abs(angle_diff(pose["theta"], math.pi / 2)) <= HEADING_TOLERANCE


def test_move_while_one_runs_is_denied_and_the_first_goes_on(
    harness: Harness, client: Client
) -> None:
    assert client.request("/api/move?marker=lobby")["status"] == "OK"
    harness.runtime.advance(1.0)
    reply = client.request("/api/move?marker=kitchen")
    assert (reply["status"], reply["error_message"]) == (
        "REQUEST_DENIED", "a move task is running: cancel it first")
    status = _status(client)
    assert (status["move_target"], status["move_status"]) == ("lobby", "running")


def test_move_cancel_stops_the_move_then_has_nothing_to_cancel(
    harness: Harness, client: Client
) -> None:
    assert client.request("/api/move?marker=kitchen")["status"] == "OK"
    harness.runtime.advance(1.0)
    reply = client.request("/api/move/cancel")
    assert (reply["command"], reply["status"], reply["error_message"]) == (
        "/api/move/cancel", "OK", "")
    harness.runtime.advance(0.5)
    status = _status(client)
    assert (status["move_status"], status["running_status"]) == ("canceled", "idle")
    again = client.request("/api/move/cancel")
    assert again["status"] == "REQUEST_DENIED"


def test_move_without_marker_or_location_is_invalid(client: Client) -> None:
    reply = client.request("/api/move?uuid=u1")
    assert (reply["uuid"], reply["status"], reply["error_message"]) == (
        "u1", "INVALID_REQUEST", "marker: marker or location is required")


def test_move_to_unknown_marker_is_invalid_marker_not_found(client: Client) -> None:
    reply = client.request("/api/move?marker=nowhere")
    assert (reply["status"], reply["error_message"]) == ("INVALID_REQUEST", "Marker Not Found")
    assert _status(client)["move_status"] == "idle"


def test_move_with_bad_floats_is_invalid(client: Client) -> None:
    for query, message in [
        ("location=1.0,abc,0", "location: must be a number, got 'abc'"),
        ("location=1.0,2.0", "location: must be x,y,theta, got '1.0,2.0'"),
        ("location=nan,2.0,0", "location: must be finite, got 'nan'"),
        ("marker=lobby&angle_offset=4", "angle_offset: must be within [-3.14, 3.14], got 4.0"),
        ("marker=lobby&distance_tolerance=x", "distance_tolerance: must be a number, got 'x'"),
    ]:
        reply = client.request(f"/api/move?{query}")
        assert (reply["status"], reply["error_message"]) == ("INVALID_REQUEST", message), query
    assert _status(client)["move_status"] == "idle"


# -- framing and robustness ---------------------------------------------------------------------


def test_unknown_command_is_invalid_request_naming_it(client: Client) -> None:
    reply = client.request("/api/fly?uuid=9")
    assert reply == {
        "type": "response", "command": "/api/fly", "uuid": "9", "status": "INVALID_REQUEST",
        "error_message": "unknown command /api/fly",
    }


def test_several_commands_in_one_send_are_answered_in_order(client: Client) -> None:
    client.send("/api/robot_info?uuid=1\n/api/markers/count?uuid=2\r\n/api/fly?uuid=3\n")
    got = [client.read() for _ in range(3)]
    assert [(p["command"], p["uuid"], p["status"]) for p in got] == [
        ("/api/robot_info", "1", "OK"),
        ("/api/markers/count", "2", "OK"),
        ("/api/fly", "3", "INVALID_REQUEST"),
    ]


def test_bad_percent_encoding_is_answered_and_the_connection_kept(client: Client) -> None:
    reply = client.request("/api/markers/delete?name=%zz&uuid=5")
    assert (reply["command"], reply["uuid"], reply["status"]) == (
        "/api/markers/delete", "5", "INVALID_REQUEST")
    assert client.request("/api/robot_info")["status"] == "OK"


def test_a_megabyte_without_newline_closes_that_connection_only(harness: Harness) -> None:
    other = harness.client()
    assert other.request("/api/robot_info")["status"] == "OK"
    bad = harness.client()
    try:
        bad.send(b"x" * 1_048_576)
    except OSError:
        pass  # the server may close before it has read everything
    try:
        tail = bad.file.read()  # until the server closes the connection
    except ConnectionResetError:
        tail = b""  # closed with our bytes unread: the kernel resets instead
    assert tail in (b"", (
        b'{"type":"response","command":"","uuid":"","status":"INVALID_REQUEST",'
        b'"error_message":"command: longer than 4096 bytes without a delimiter"}\n'))
    assert other.request("/api/robot_info")["status"] == "OK"
    assert harness.client().request("/api/robot_info")["status"] == "OK"


# -- markers ------------------------------------------------------------------------------------


def test_markers_insert_query_count_delete_round_trip(harness: Harness, client: Client) -> None:
    count = client.request("/api/markers/count")
    assert (count["status"], count["results"]) == ("OK", {"count": 18})
    assert client.request("/api/markers/insert?name=dock_2&type=11&num=3")["status"] == "OK"
    listed = client.request("/api/markers/query_list?floor=1")
    assert listed["status"] == "OK"
    marker = listed["results"]["dock_2"]
    pose = harness.runtime.status().pose
    assert (marker["marker_name"], marker["key"], marker["floor"]) == ("dock_2", 11, 1)
    assert marker["pose"]["position"] == {"x": pose.x, "y": pose.y, "z": 0.0}
    o = marker["pose"]["orientation"]
    assert (o["x"], o["y"]) == (0.0, 0.0)
    assert abs(angle_diff(quaternion_to_yaw(0.0, 0.0, o["z"], o["w"]), pose.theta)) < 1e-9
    assert client.request("/api/markers/count")["results"] == {"count": 19}
    assert client.request("/api/markers/delete?name=dock_2")["status"] == "OK"
    assert "dock_2" not in client.request("/api/markers/query_list")["results"]
    again = client.request("/api/markers/delete?name=dock_2")
    assert (again["status"], again["error_message"]) == ("INVALID_REQUEST", "Marker Not Found")


def test_markers_insert_existing_name_moves_it(harness: Harness, client: Client) -> None:
    assert client.request("/api/markers/insert?name=lobby")["status"] == "OK"
    marker = client.request("/api/markers/query_list")["results"]["lobby"]
    assert marker["pose"]["position"]["x"] == harness.runtime.status().pose.x
    assert client.request("/api/markers/count")["results"] == {"count": 18}


def test_markers_query_list_filters_by_floor(client: Client) -> None:
    floor2 = client.request("/api/markers/query_list?floor=2")["results"]
    assert len(floor2) == 23 and {m["floor"] for m in floor2.values()} == {2}
    assert floor2["lift_1_outside"]["key"] == 3
    every = client.request("/api/markers/query_list")["results"]
    assert every["corridor_west"]["floor"] == 1  # the current floor wins a name clash
    assert "room_205" in every and "kitchen" in every
    missing = client.request("/api/markers/query_list?floor=9")
    assert (missing["status"], missing["error_message"]) == (
        "INVALID_REQUEST", "floor: no floor 9")


# -- estop, joystick, location, map -------------------------------------------------------------


def test_estop_sets_and_clears_the_soft_estop(harness: Harness, client: Client) -> None:
    assert client.request("/api/estop?flag=true")["status"] == "OK"
    harness.runtime.advance(0.1)
    status = _status(client)
    assert (status["soft_estop_state"], status["hard_estop_state"], status["estop_state"]) == (
        True, False, True)
    assert client.request("/api/estop?flag=false")["status"] == "OK"
    harness.runtime.advance(0.1)
    assert _status(client)["estop_state"] is False
    bad = client.request("/api/estop?flag=yes")
    assert (bad["status"], bad["error_message"]) == (
        "INVALID_REQUEST", "flag: must be true or false, got 'yes'")


def test_joy_control_is_clamped_and_stops_half_a_second_after_the_last_command(
    harness: Harness, client: Client
) -> None:
    # Turning in place (safe anywhere): 5 rad/s asked, 1.0 rad/s allowed (the runtime's own
    # limit is 1.5 rad/s, so a saturated speed at 1.0 shows the dialect's clamp).
    for _ in range(8):
        reply = client.request("/api/joy_control?angular_velocity=5&linear_velocity=0")
        assert reply["status"] == "OK"
        harness.runtime.advance(0.4)
    assert 0.9 < harness.runtime.status().angular <= 1.0 + 1e-6
    harness.runtime.advance(1.0)
    assert abs(harness.runtime.status().angular) < 0.05
    missing = client.request("/api/joy_control?linear_velocity=0.1")
    assert (missing["status"], missing["error_message"]) == (
        "INVALID_REQUEST", "angular_velocity: is required")


def test_joy_control_during_a_move_is_denied(harness: Harness, client: Client) -> None:
    assert client.request("/api/move?marker=lobby")["status"] == "OK"
    harness.runtime.advance(0.5)
    reply = client.request("/api/joy_control?angular_velocity=0.5&linear_velocity=0")
    assert reply["status"] == "REQUEST_DENIED"


def test_get_current_location_lists_near_markers_nearest_first(client: Client) -> None:
    reply = client.request("/api/get_current_location?distance_threshold=4")
    assert reply["status"] == "OK"
    r = reply["results"]
    assert (r["current_floor"], r["running_status"]) == (1, "idle")
    names = [m["marker_name"] for m in r["near_markers"]]
    assert names == ["initial", "front_desk"]
    assert r["near_markers"][0]["distance"] < 0.1 and r["near_markers"][0]["key"] == 0
    bad = client.request("/api/get_current_location?distance_threshold=0")
    assert (bad["status"], bad["error_message"]) == (
        "INVALID_REQUEST", "distance_threshold: must be >= 0.01, got 0.0")


def test_map_get_current_map_reports_name_floor_and_grid(client: Client) -> None:
    reply = client.request("/api/map/get_current_map")
    assert (reply["status"], reply["results"]) == ("OK", {
        "hotel_id": "floor1", "map_name": "floor1", "floor": "1",
        "info": {"resolution": 0.05, "width": 820, "height": 500,
                 "origin_x": -0.5, "origin_y": -0.5},
    })


# -- more markers, relocalization, maps ----------------------------------------------------------


def test_marker_types_front_desk_and_custom_read_back_and_others_are_refused(
    harness: Harness, client: Client
) -> None:
    for name, marker_type in (("desk", 1), ("cart_bay", 1007), ("gate_2", 7), ("pile", 11)):
        command = f"/api/markers/insert_by_pose?name={name}&x=5&y=12&theta=0&type={marker_type}"
        assert client.request(command)["status"] == "OK"
    listed = client.request("/api/markers/query_list?floor=1")["results"]
    assert {n: listed[n]["key"] for n in ("desk", "cart_bay", "gate_2", "pile")} == {
        "desk": 1, "cart_bay": 1007, "gate_2": 7, "pile": 11}
    brief = client.request("/api/markers/query_brief")["results"]
    assert (brief["desk"], brief["cart_bay"]) == ("1-1", "1007-1")
    kinds = {p.name: p.kind.value for p in harness.runtime.store.points(map_name="floor1")}
    assert (kinds["desk"], kinds["cart_bay"], kinds["pile"]) == ("front-desk", "custom", "charger")
    for bad in ("2", "5", "999", "-1", "x"):
        reply = client.request(f"/api/markers/insert?name=odd&type={bad}")
        assert reply["status"] == "INVALID_REQUEST", reply
        assert reply["error_message"].startswith("type: "), reply


def test_markers_query_brief_gives_type_dash_floor(client: Client) -> None:
    reply = client.request("/api/markers/query_brief")
    assert reply["status"] == "OK"
    r = reply["results"]
    assert (r["lobby"], r["charger"], r["lift_1_inside"], r["room_205"]) == (
        "0-1", "11-1", "4-1", "0-2")
    assert r["corridor_west"] == "0-1"  # the current floor wins a name clash
    # initial, corridor_west/east and lift_1_outside/inside are on all three floors,
    # lift_2_outside/inside on floors 1 and 2
    assert len(r) == 18 + 23 + 15 - 7 - 5


def test_markers_insert_by_pose_on_another_floor_and_bad_theta(client: Client) -> None:
    reply = client.request(
        "/api/markers/insert_by_pose?name=205_door&x=-0.1&y=1.0&theta=0.5&floor=2&type=7")
    assert reply["status"] == "OK"
    marker = client.request("/api/markers/query_list?floor=2")["results"]["205_door"]
    assert (marker["floor"], marker["key"], marker["pose"]["position"]) == (
        2, 7, {"x": -0.1, "y": 1.0, "z": 0.0})
    o = marker["pose"]["orientation"]
    assert abs(quaternion_to_yaw(0.0, 0.0, o["z"], o["w"]) - 0.5) < 1e-9
    for query, message in [
        ("name=a&x=1&y=1&theta=4", "theta: must be within [-pi, pi], got 4.0"),
        ("name=a&x=1&y=1&theta=0&floor=7", "floor: no floor 7"),
        ("name=a&x=1&theta=0", "y: is required"),
        ("x=1&y=1&theta=0", "name: is required"),
    ]:
        bad = client.request(f"/api/markers/insert_by_pose?{query}")
        assert (bad["status"], bad["error_message"]) == ("INVALID_REQUEST", message), query


def test_position_adjust_puts_the_robot_at_the_marker(harness: Harness, client: Client) -> None:
    assert client.request("/api/position_adjust?marker=front_desk")["status"] == "OK"
    harness.runtime.advance(1.0)
    pose = _status(client)["current_pose"]
    assert math.hypot(pose["x"] - 5.0, pose["y"] - 6.0) < 0.1
    assert abs(angle_diff(pose["theta"], math.pi / 2)) < 0.1
    missing = client.request("/api/position_adjust?marker=nowhere")
    assert (missing["status"], missing["error_message"]) == ("INVALID_REQUEST", "Marker Not Found")


def test_position_adjust_is_denied_during_a_move(harness: Harness, client: Client) -> None:
    assert client.request("/api/move?marker=lobby")["status"] == "OK"
    harness.runtime.advance(0.5)
    assert client.request("/api/position_adjust?marker=front_desk")["status"] == "REQUEST_DENIED"


def test_position_adjust_by_pose_on_this_floor_and_on_another(
    harness: Harness, client: Client
) -> None:
    assert client.request("/api/position_adjust_by_pose?x=5.5&y=12.5&theta=0")["status"] == "OK"
    harness.runtime.advance(1.0)
    pose = _status(client)["current_pose"]
    assert math.hypot(pose["x"] - 5.5, pose["y"] - 12.5) < 0.1
    reply = client.request("/api/position_adjust_by_pose?x=4.0&y=11.0&theta=1.5707963&floor=2")
    assert reply["status"] == "OK"
    harness.runtime.advance(1.0)
    status = _status(client)
    assert status["current_floor"] == 2
    assert math.hypot(status["current_pose"]["x"] - 4.0, status["current_pose"]["y"] - 11.0) < 0.1
    current = client.request("/api/map/get_current_map")["results"]
    assert (current["map_name"], current["floor"]) == ("floor2", "2")
    bad = client.request("/api/position_adjust_by_pose?x=a&y=1&theta=0")
    assert (bad["status"], bad["error_message"]) == (
        "INVALID_REQUEST", "x: must be a number, got 'a'")


def test_map_list_gives_each_map_its_floor(client: Client) -> None:
    reply = client.request("/api/map/list")
    assert (reply["status"], reply["results"]) == (
        "OK", {"floor1": [1], "floor2": [2], "floor3": [3]})


# -- parameters ----------------------------------------------------------------------------------


def test_get_params_reports_the_current_speed_limits(client: Client) -> None:
    reply = client.request("/api/get_params")
    assert (reply["status"], reply["results"]) == (
        "OK", {"max_speed_linear": 0.6, "max_speed_angular": 1.5})


def test_set_params_clamps_and_always_answers_ok(harness: Harness, client: Client) -> None:
    assert client.request("/api/set_params?max_speed_linear=0.5")["status"] == "OK"
    assert client.request("/api/get_params")["results"]["max_speed_linear"] == 0.5
    # Below the vendor's range -> its minimum; above polynav's -> polynav's maximum, which is
    # the robot profile's limit (the demo robot turns at most 2 rad/s).
    reply = client.request("/api/set_params?max_speed_linear=0.01&max_speed_angular=9")
    assert reply["status"] == "OK"
    assert client.request("/api/get_params")["results"] == {
        "max_speed_linear": 0.1, "max_speed_angular": 2.0}
    assert harness.runtime.settings().max_linear_velocity == 0.1
    # Bad values and unknown names change nothing, and still answer OK.
    for query in ("max_speed_linear=fast", "max_speed_ratio=0.5", "colour=red"):
        assert client.request(f"/api/set_params?{query}")["status"] == "OK"
    assert client.request("/api/get_params")["results"] == {
        "max_speed_linear": 0.1, "max_speed_angular": 2.0}


def test_map_list_info_gives_each_map_its_grid(client: Client) -> None:
    reply = client.request("/api/map/list_info")
    grid = {"resolution": 0.05, "height": 500, "width": 820, "origin_x": -0.5, "origin_y": -0.5}
    assert (reply["status"], reply["results"]) == ("OK", {
        "floor1": [{"floor": 1, **grid}], "floor2": [{"floor": 2, **grid}],
        "floor3": [{"floor": 3, **grid}]})


def test_map_set_current_map_moves_the_robot_to_that_floor(
    harness: Harness, client: Client
) -> None:
    bad_floor = client.request("/api/map/set_current_map?map_name=floor2&floor=1")
    assert (bad_floor["status"], bad_floor["error_message"]) == (
        "INVALID_REQUEST", "floor: map 'floor2' is not on floor 1")
    unknown = client.request("/api/map/set_current_map?map_name=attic&floor=4")
    assert (unknown["status"], unknown["error_message"]) == (
        "INVALID_REQUEST", "map 'attic' not found")
    reply = client.request("/api/map/set_current_map?hotel_id=floor2&floor=2")  # legacy name
    assert (reply["command"], reply["status"]) == ("/api/map/set_current_map", "OK")
    harness.runtime.advance(1.0)
    assert _status(client)["current_floor"] == 2
    current = client.request("/api/map/get_current_map")["results"]
    assert (current["map_name"], current["floor"]) == ("floor2", "2")
    assert client.request("/api/markers/count")["results"] == {"count": 23}


def test_map_set_current_map_is_denied_during_a_move(harness: Harness, client: Client) -> None:
    assert client.request("/api/move?marker=lobby")["status"] == "OK"
    harness.runtime.advance(0.5)
    reply = client.request("/api/map/set_current_map?map_name=floor2&floor=2")
    assert reply["status"] == "REQUEST_DENIED"


# -- request_data --------------------------------------------------------------------------------


def test_request_data_streams_robot_status_callbacks(harness: Harness, client: Client) -> None:
    reply = client.request("/api/request_data?topic=robot_status&frequency=2&uuid=s")
    assert (reply["command"], reply["uuid"], reply["status"]) == ("/api/request_data", "s", "OK")
    first = client.push("callback", "robot_status")
    assert set(first) == {"type", "topic", "results"}
    assert set(first["results"]) == set(_status(harness.client()))
    assert client.request("/api/move?marker=lobby")["status"] == "OK"
    client.pushed.clear()
    harness.runtime.advance(1.0)
    later = client.push("callback", "robot_status")
    assert later["results"]["move_target"] == "lobby"


def test_request_data_streams_robot_velocity_and_rejects_bad_requests(
    harness: Harness, client: Client
) -> None:
    assert client.request("/api/request_data?topic=robot_velocity")["status"] == "OK"
    packet = client.push("callback", "robot_velocity")
    assert packet["results"] == {"angular": 0.0, "linear": 0.0}
    assert client.request("/api/request_data?topic=robot_velocity&switch=off")["status"] == "OK"
    for query, message in [
        ("topic=weather", "topic: unknown topic 'weather'"),
        ("topic=robot_status&frequency=0", "frequency: must be in (0, 20] Hz, got 0"),
        ("topic=robot_status&switch=maybe", "switch: must be on or off, got 'maybe'"),
        ("frequency=1", "topic: is required"),
    ]:
        reply = client.request(f"/api/request_data?{query}")
        assert (reply["status"], reply["error_message"]) == ("INVALID_REQUEST", message), query


# -- notifications -------------------------------------------------------------------------------


def _notifications(client: Client, count: int) -> list[dict[str, Any]]:
    return [client.push("notification") for _ in range(count)]


def test_move_notifications_go_to_every_client(harness: Harness, client: Client) -> None:
    listener = harness.client()
    assert listener.request("/api/robot_info")["status"] == "OK"  # connected before the move
    assert client.request("/api/move?marker=lobby")["status"] == "OK"
    _wait_move_quietly(harness)
    started, finished = _notifications(listener, 2)
    assert started == {
        "type": "notification", "code": "01001", "level": "info",
        "description": "The move task is started.", "data": {"target": "lobby"},
    }
    assert (finished["code"], finished["level"], finished["description"]) == (
        "01002", "info", "The move task is finished.")
    assert finished["data"]["target"] == "lobby"
    assert 3.0 < finished["data"]["distance"] < 10.0
    assert [n["code"] for n in _notifications(client, 2)] == ["01001", "01002"]


def _wait_move_quietly(h: Harness) -> None:
    assert h.runtime.advance_until(
        lambda: h.runtime.status().navigation_state in ("succeeded", "failed", "canceled"),
        timeout=MOVE_TIMEOUT,
    )


def test_cancel_notification_names_the_marker_of_an_offset_move(
    harness: Harness, client: Client
) -> None:
    assert client.request("/api/move?marker=kitchen&angle_offset=0.5")["status"] == "OK"
    harness.runtime.advance(1.0)
    client.send("/api/move/cancel")
    harness.runtime.advance(0.5)
    # The move's own notices name the marker; the lobby gate's (01030/01031, when the route
    # reached it before the cancel: test_door_notices.py) name it too.
    codes = [client.push("notification")]
    while codes[-1]["code"] != "01004":
        codes.append(client.push("notification"))
    assert [n["code"] for n in codes if n["code"] not in ("01030", "01031")] == ["01001", "01004"]
    assert all(n["data"]["target"] == "kitchen" for n in codes)


def test_failed_move_notification_is_a_warning(harness: Harness, client: Client) -> None:
    assert client.request("/api/move?location=10.0,8.5,0")["status"] == "OK"  # in a wall
    _wait_move_quietly(harness)
    started = client.push("notification")
    failed = client.push("notification")
    while failed["code"] != "01003":
        failed = client.push("notification")
    assert (started["code"], started["data"]) == ("01001", {"target": ""})
    assert (failed["level"], failed["data"]["target"]) == ("warning", "")


def test_estop_notifications_on_and_off(harness: Harness, client: Client) -> None:
    client.send("/api/estop?flag=true")
    harness.runtime.advance(0.1)
    client.send("/api/estop?flag=false")
    harness.runtime.advance(0.1)
    assert [(n["code"], n["description"], n["data"]) for n in _notifications(client, 2)] == [
        ("02003", "Estop on.", {}), ("02004", "Estop off.", {})]


# Entries of yunji-api.endpoints.json this module tests (collected by test_endpoints.py).
COVERED: dict[str, str] = {
    "cmd 1.1 /api/move": "test_move_to_marker_succeeds_within_5_cm_and_0_1_rad",
    "cmd 2 /api/move/cancel": "test_move_cancel_stops_the_move_then_has_nothing_to_cancel",
    "cmd 3 /api/robot_status": "test_robot_status_has_every_field_of_the_spec",
    "cmd 4 /api/robot_info": "test_robot_info_reports_the_product_id",
    "cmd 5.1 /api/markers/insert": "test_markers_insert_query_count_delete_round_trip",
    "cmd 5.2 /api/markers/query_list": "test_markers_query_list_filters_by_floor",
    "cmd 5.3 /api/markers/delete": "test_markers_insert_query_count_delete_round_trip",
    "cmd 5.4 /api/markers/count": "test_markers_insert_query_count_delete_round_trip",
    "cmd 6 /api/joy_control":
        "test_joy_control_is_clamped_and_stops_half_a_second_after_the_last_command",
    "cmd 7 /api/estop": "test_estop_sets_and_clears_the_soft_estop",
    "cmd 5.5 /api/markers/query_brief": "test_markers_query_brief_gives_type_dash_floor",
    "cmd 5.6 /api/markers/insert_by_pose":
        "test_markers_insert_by_pose_on_another_floor_and_bad_theta",
    "cmd 8.1 /api/position_adjust": "test_position_adjust_puts_the_robot_at_the_marker",
    "cmd 8.2 /api/position_adjust_by_pose":
        "test_position_adjust_by_pose_on_this_floor_and_on_another",
    "cmd 9.1 /api/request_data?topic=robot_status":
        "test_request_data_streams_robot_status_callbacks",
    "cmd 9.3 /api/request_data?topic=robot_velocity":
        "test_request_data_streams_robot_velocity_and_rejects_bad_requests",
    "cmd 11 /api/set_params": "test_set_params_clamps_and_always_answers_ok",
    "cmd 12 /api/get_params": "test_get_params_reports_the_current_speed_limits",
    "cmd 14.1 /api/map/list": "test_map_list_gives_each_map_its_floor",
    "cmd 14.2 /api/map/set_current_map":
        "test_map_set_current_map_moves_the_robot_to_that_floor",
    "cmd 14.4 /api/map/list_info": "test_map_list_info_gives_each_map_its_grid",
    "cmd 14.3 /api/map/get_current_map": "test_map_get_current_map_reports_name_floor_and_grid",
    "cmd 16.1 /api/software/get_version": "test_software_get_version_is_polynav_version",
    "cmd 23 /api/get_current_location":
        "test_get_current_location_lists_near_markers_nearest_first",
}

COVERED.update({
    "notify 10 01001": "test_move_notifications_go_to_every_client",
    "notify 10 01002": "test_move_notifications_go_to_every_client",
    "notify 10 01003": "test_failed_move_notification_is_a_warning",
    "notify 10 01004": "test_cancel_notification_names_the_marker_of_an_offset_move",
    "notify 10 02003": "test_estop_notifications_on_and_off",
    "notify 10 02004": "test_estop_notifications_on_and_off",
})
