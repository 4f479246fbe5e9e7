"""Robot configuration over real HTTP (galileo-http-a E-28–E-30)."""

from __future__ import annotations

import pytest

from polynav.protocols.galileo.system_config import ORDER
from tests.protocols.galileo.conftest import Harness

COVERED = {
    "GET /api/v1/system/config": "test_config_lists_every_key_with_the_runtime_settings",
    "POST /api/v1/system/config": "test_changing_config_changes_the_robot_all_or_nothing",
    "DELETE /api/v1/system/config": "test_a_key_goes_back_to_its_default",
}


def test_config_lists_every_key_with_the_runtime_settings(galileo: Harness) -> None:
    body = galileo.ok("GET", "/system/config")
    assert list(body) == list(ORDER)
    settings = galileo.runtime.settings()
    assert body["lf_linear_v"] == body["navigation_speed"] == settings.max_linear_velocity
    assert body["robot_radius"] == settings.robot_radius
    assert body["go_charge_percentage"] == settings.low_battery_percent
    assert body["slam_type"] == "lidar" and body["maps"] == [] and body["auto_charge"] is False
    for key in ("lf_kp", "lf_look_ahead_dist", "use_smooth_switch_map"):
        assert isinstance(body[key], float), key
    assert isinstance(body["lf_move_direction"], int)


def test_changing_config_changes_the_robot_all_or_nothing(galileo: Harness) -> None:
    body = galileo.ok("POST", "/system/config", json={
        "lf_linear_v": 0.4, "lf_xy_goal_tolerance": 0.1, "lf_kp": 2.5,
        "maps": [{"map": "floor1", "path": "default"}], "unknown_key": 1,
    })
    assert body["lf_linear_v"] == body["navigation_speed"] == 0.4
    assert body["lf_kp"] == 2.5 and body["maps"] == [{"map": "floor1", "path": "default"}]
    assert "unknown_key" not in body
    settings = galileo.runtime.settings()
    assert settings.max_linear_velocity == 0.4 and settings.xy_goal_tolerance == 0.1
    assert galileo.ok("GET", "/system/config") == body
    # Teleop is now limited to the new maximum.
    for _ in range(15):
        galileo.ok("PUT", "/system/speed", json={"speed_x": 1.0, "speed_angle": 0.0})
        galileo.runtime.advance(0.2)
    assert galileo.ok("GET", "/system/speed")["speed_x"] == pytest.approx(0.4, abs=0.02)


@pytest.mark.parametrize("body", [
    {"lf_linear_v": 0.3, "lf_kp": "high"},
    {"lf_linear_v": 0.3, "robot_radius": 5.0},
    {"lf_linear_v": 0.3, "slam_type": "camera"},
    {"lf_linear_v": 0.3, "maps": ["floor1"]},
    {"lf_linear_v": 0.3, "auto_charge": "perhaps"},
    {"lf_linear_v": 0.3, "navigation_speed": 0.5},
    {"lf_kp": 3.0, "wifi_ssid": "nowhere", "wifi_password": "x"},
])
def test_bad_config_changes_nothing(galileo: Harness, body: dict[str, object]) -> None:
    before = galileo.ok("GET", "/system/config")
    reply = galileo.post("/system/config", body)
    assert reply.status_code == 400 and reply.json()["status"] == "error"
    assert galileo.ok("GET", "/system/config") == before


def test_config_keys_in_the_query_string_are_parsed(galileo: Harness) -> None:
    reply = galileo.request("POST", "/system/config",
                            params={"lf_kp": "2.5", "auto_charge": "true", "lf_linear_v": "0.5"})
    assert reply.status_code == 200, reply.text
    body = reply.json()
    assert (body["lf_kp"], body["auto_charge"], body["lf_linear_v"]) == (2.5, True, 0.5)


def test_a_key_goes_back_to_its_default(galileo: Harness) -> None:
    galileo.ok("POST", "/system/config", json={"lf_linear_v": 0.3, "lf_kp": 4.0})
    assert galileo.ok("DELETE", "/system/config", params={"key": "lf_linear_v"}) == {
        "status": "ok"}
    assert galileo.ok("DELETE", "/system/config", params={"key": "lf_kp"}) == {"status": "ok"}
    body = galileo.ok("GET", "/system/config")
    assert body["lf_linear_v"] == 0.6 and body["lf_kp"] == 1.0
    assert galileo.delete("/system/config", key="nope").status_code == 400
    assert galileo.delete("/system/config").status_code == 400
