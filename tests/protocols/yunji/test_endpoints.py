"""Coverage of ``yunji-api.endpoints.json``: every entry (reserved codes excepted) has a test.

``COVERED`` names the test in ``test_server.py`` that exercises an implemented command.
``PENDING_COMMANDS`` and the notification codes are not implemented yet: each has a strict xfail
test below that asks for what the spec promises (an ``OK`` reply, a produced notification) and
genuinely fails today. When a command is implemented its xfail starts passing, which fails the
suite (strict): move the entry to ``COVERED`` with a real test in ``test_server.py``.
"""

from __future__ import annotations

import importlib
import json
from pathlib import Path
from typing import Any

import pytest

from tests.conftest import SHARED
from tests.protocols.yunji import test_server
from tests.protocols.yunji.conftest import Client

SPEC = SHARED / "spec" / "yunji-api.endpoints.json"


def _entries(path: Path) -> list[dict[str, Any]]:
    if not path.is_file():
        return []
    data = json.loads(path.read_text(encoding="utf-8"))
    assert isinstance(data, list)
    return data


def _key(entry: dict[str, Any]) -> str:
    return f"{entry['method']} {entry['section']} {entry['path']}"


ENTRIES = _entries(SPEC)
LIVE = [e for e in ENTRIES if not e.get("reserved")]

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

# Not implemented yet: entry -> a request the spec says is answered OK on the demo site.
PENDING_COMMANDS: dict[str, str] = {
    "cmd 1.2 /api/move": "/api/move?markers=lobby,front_desk&count=1",
    "cmd 9.2 /api/request_data?topic=human_detection":
        "/api/request_data?topic=human_detection&frequency=0.5",
    "cmd 13.1 /api/wifi/list": "/api/wifi/list",
    "cmd 13.2 /api/wifi/connect": "/api/wifi/connect?SSID=polynav&password=secret",
    "cmd 13.3 /api/wifi/get_active_connection": "/api/wifi/get_active_connection",
    "cmd 13.4 /api/wifi/info": "/api/wifi/info",
    "cmd 13.5 /api/wifi/detail_list": "/api/wifi/detail_list",
    "cmd 14.5 /api/map/accessible_point_query": "/api/map/accessible_point_query?x=8.0&y=8.5",
    "cmd 14.6 /api/map/distance_probe": "/api/map/distance_probe?x=8.0&y=8.5",
    "cmd 15 /api/shutdown": "/api/shutdown?reboot=true",
    "cmd 16.2 /api/software/check_for_update": "/api/software/check_for_update",
    "cmd 16.3 /api/software/update": "/api/software/update",
    "cmd 16.4 /api/software/restart": "/api/software/restart",
    "cmd 17.1 /api/LED/set_luminance": "/api/LED/set_luminance?value=50",
    "cmd 17.2 /api/LED/set_color": "/api/LED/set_color?r=255&g=0&b=0",
    "cmd 18 /api/diagnosis/get_result": "/api/diagnosis/get_result",
    "cmd 19 /api/get_power_status": "/api/get_power_status",
    "cmd 20 /api/get_planned_path": "/api/get_planned_path",
    "cmd 21 /api/lift_status": "/api/lift_status",
    "cmd 22 /api/make_plan":
        "/api/make_plan?start_x=8.0&start_y=8.5&start_floor=1&goal_x=5.5&goal_y=12.5&goal_floor=1",
}

COVERED.update({
    "notify 10 01001": "test_move_notifications_go_to_every_client",
    "notify 10 01002": "test_move_notifications_go_to_every_client",
    "notify 10 01003": "test_failed_move_notification_is_a_warning",
    "notify 10 01004": "test_cancel_notification_names_the_marker_of_an_offset_move",
    "notify 10 02003": "test_estop_notifications_on_and_off",
    "notify 10 02004": "test_estop_notifications_on_and_off",
})

PENDING_NOTIFICATIONS = [
    _key(e) for e in LIVE if e["method"] == "notify" and _key(e) not in COVERED
]

_pending = pytest.mark.xfail(strict=True, reason="not implemented yet")


@pytest.mark.skipif(not ENTRIES, reason="shared/spec is not beside the checkout")
def test_every_endpoint_entry_has_a_test_or_a_pending_xfail() -> None:
    keys = [_key(e) for e in LIVE]
    assert len(keys) == len(set(keys)), "entry keys must be unique"
    accounted = set(COVERED) | set(PENDING_COMMANDS) | set(PENDING_NOTIFICATIONS)
    assert sorted(set(keys) - accounted) == []
    assert sorted(accounted - set(keys)) == []  # nothing stale
    assert set(COVERED).isdisjoint(PENDING_COMMANDS)
    for key, test_name in COVERED.items():
        assert callable(getattr(test_server, test_name, None)), f"{key}: no test {test_name}"


@_pending
@pytest.mark.parametrize("key", sorted(PENDING_COMMANDS))
def test_pending_command_is_answered_ok(key: str, client: Client) -> None:
    command = PENDING_COMMANDS[key]
    reply = client.request(command)
    assert (reply["command"], reply["status"]) == (command.split("?")[0], "OK"), reply


@_pending
@pytest.mark.parametrize("key", PENDING_NOTIFICATIONS)
def test_pending_notification_is_produced(key: str) -> None:
    code = key.split()[-1]
    events = importlib.import_module("polynav.protocols.yunji.events")
    assert code in events.NOTIFICATIONS
