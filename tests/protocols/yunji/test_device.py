"""The robot as a device over a real TCP socket: Wi-Fi, LED strip, self-diagnosis, power status,
software update/restart, shutdown and reboot, and the device notifications (02000, 02005,
02006, 03001).

Simulated time advances only when a test calls ``runtime.advance`` (see conftest).
"""

from __future__ import annotations

import time
from typing import Any

from polynav.geometry import Pose2D
from polynav.runtime.settings import RobotSettings
from tests.protocols.yunji.conftest import Client, Harness


def _ok(client: Client, command: str) -> Any:
    reply = client.request(command)
    assert (reply["command"], reply["status"], reply["error_message"]) == (
        command.split("?")[0], "OK", ""), reply
    return reply.get("results")


def _invalid(client: Client, command: str, field: str) -> None:
    reply = client.request(command)
    assert reply["status"] == "INVALID_REQUEST", (command, reply)
    assert reply["error_message"].startswith(f"{field}: "), (command, reply)


def _notification(client: Client, code: str) -> dict[str, Any]:
    packet = client.push("notification")
    while packet["code"] != code:
        packet = client.push("notification")
    return packet


# -- Wi-Fi -------------------------------------------------------------------------------------


def test_wifi_list_shows_the_networks_in_range_by_strength(
    harness: Harness, client: Client
) -> None:
    near = _ok(client, "/api/wifi/list")
    # By the lobby: the office networks are strong, the hotel's (a floor up) weak, the guest
    # network (25 m and many walls away) out of range.
    assert set(near) == {"polynav-office", "polynav-office-5G", "polynav-hotel"}
    assert near["polynav-office"] > near["polynav-office-5G"] > near["polynav-hotel"] > 0
    assert all(isinstance(v, int) and 0 <= v <= 100 for v in near.values())
    harness.runtime.set_initial_pose(Pose2D(31.6, 21.0, 1.5708))  # the kitchen
    harness.runtime.advance(0.5)
    far = _ok(client, "/api/wifi/list")
    assert "polynav-guest" in far
    assert far.get("polynav-office", 0) < near["polynav-office"]


def test_wifi_connect_checks_the_password_and_remembers_it(client: Client) -> None:
    assert _ok(client, "/api/wifi/get_active_connection") == ""
    assert _ok(client, "/api/wifi/info")["IPaddr"] == ""
    _invalid(client, "/api/wifi/connect?SSID=polynav-office&password=guess", "password")
    _invalid(client, "/api/wifi/connect?SSID=polynav-office", "password")  # never joined
    _invalid(client, "/api/wifi/connect?SSID=polynav-guest", "SSID")  # out of range
    _invalid(client, "/api/wifi/connect?password=x", "SSID")
    _ok(client, "/api/wifi/connect?SSID=polynav-office&password=office-2437")
    assert _ok(client, "/api/wifi/get_active_connection") == "polynav-office"
    _ok(client, "/api/wifi/connect?SSID=polynav-office-5G&password=office-5260")
    _ok(client, "/api/wifi/connect?SSID=polynav-office")  # joined before: no password
    assert _ok(client, "/api/wifi/get_active_connection") == "polynav-office"


def test_wifi_info_gives_the_address_and_the_mac(client: Client) -> None:
    before = _ok(client, "/api/wifi/info")
    assert before["IPaddr"] == ""
    mac = before["HWaddr"]
    assert len(mac.split(":")) == 6 and all(len(part) == 2 for part in mac.split(":"))
    _ok(client, "/api/wifi/connect?SSID=polynav-office&password=office-2437")
    after = _ok(client, "/api/wifi/info")
    assert after["IPaddr"].startswith("192.0.2.") and after["HWaddr"] == mac


def test_wifi_detail_list_describes_each_network(client: Client) -> None:
    _ok(client, "/api/wifi/connect?SSID=polynav-office-5G&password=office-5260")
    details = _ok(client, "/api/wifi/detail_list")
    assert details["polynav-office-5G"] == {
        "SSID": "polynav-office-5G", "SIGNAL": details["polynav-office-5G"]["SIGNAL"],
        "ACTIVE": True, "FREQ": "5260 MHz", "SECURITY": "WPA WPA2",
    }
    assert details["polynav-office"]["ACTIVE"] is False
    assert details["polynav-office"]["FREQ"] == "2437 MHz"
    assert set(details) == set(_ok(client, "/api/wifi/list"))


# -- LED ---------------------------------------------------------------------------------------


def test_led_luminance_is_set_kept_and_checked(harness: Harness, client: Client) -> None:
    _ok(client, "/api/LED/set_luminance?value=35")
    assert harness.runtime.device.light.luminance == 35.0
    # Persisted: the site store has it for the next start.
    assert RobotSettings.from_stored(harness.runtime.store.settings()).led_luminance == 35.0
    _invalid(client, "/api/LED/set_luminance?value=101", "value")
    _invalid(client, "/api/LED/set_luminance?value=-1", "value")
    _invalid(client, "/api/LED/set_luminance", "value")
    _invalid(client, "/api/LED/set_luminance?value=bright", "value")
    assert harness.runtime.device.light.luminance == 35.0


def test_led_color_is_set_and_all_zero_does_not_take_effect(
    harness: Harness, client: Client
) -> None:
    _ok(client, "/api/LED/set_color?r=100&g=50&b=0")
    light = harness.runtime.device.light
    assert (light.red, light.green, light.blue) == (100.0, 50.0, 0.0)
    reply = client.request("/api/LED/set_color?r=0&g=0&b=0")
    assert reply["status"] == "UNKNOWN_ERROR" and "all 0" in reply["error_message"]
    assert harness.runtime.device.light.red == 100.0
    _invalid(client, "/api/LED/set_color?r=255&g=0&b=0", "r")
    _invalid(client, "/api/LED/set_color?r=10&g=0", "b")


# -- diagnosis, power --------------------------------------------------------------------------


def test_diagnosis_reports_each_part_and_a_blocked_lidar_fails(
    harness: Harness, client: Client
) -> None:
    assert client.request("/api/diagnosis/get_result")["status"] == "UNKNOWN_ERROR"  # booting
    harness.runtime.advance(12.0)  # two rounds of checks
    results = _ok(client, "/api/diagnosis/get_result")
    assert set(results) >= {"sensor_core", "motor_core_right", "motor_core_left", "radio_core",
                            "power_core", "laser", "IMU", "CAN"}
    for part, item in results.items():
        assert set(item) == {"status", "time_stamp", "total_count", "success_count"}, part
        assert item["status"] is True and item["total_count"] == item["success_count"] >= 2
        assert abs(item["time_stamp"] - time.time()) < 60.0
    harness.runtime.simulation.inject_fault("laser_slot_object")
    harness.runtime.advance(10.0)
    laser = _ok(client, "/api/diagnosis/get_result")["laser"]
    assert laser["status"] is False and laser["success_count"] == laser["total_count"] - 1


def test_get_power_status_follows_the_battery_and_the_charger(
    harness: Harness, client: Client
) -> None:
    off = _ok(client, "/api/get_power_status")
    assert set(off) == {"battery_capacity", "battery_current", "battery_voltage",
                        "charge_voltage", "charger_connected_notice", "head_current"}
    assert off["battery_capacity"] == 80 and off["charger_connected_notice"] is False
    assert off["battery_current"] < 0.0 and off["charge_voltage"] == 0.0
    assert 22.0 < off["battery_voltage"] < 29.4 and off["head_current"] > 0.0
    assert client.request("/api/move?marker=charger")["status"] == "OK"
    for _ in range(240):
        harness.runtime.advance(0.5)
        if harness.runtime.status().charging:
            break
    harness.runtime.advance(1.0)
    on = _ok(client, "/api/get_power_status")
    assert on["charger_connected_notice"] is True
    assert on["battery_current"] > 0.0 and on["charge_voltage"] == 29.4


# -- software ----------------------------------------------------------------------------------


def test_check_for_update_reports_the_installed_version_as_latest(client: Client) -> None:
    version = _ok(client, "/api/software/get_version")
    assert _ok(client, "/api/software/check_for_update") == {
        "version_latest": version, "version_current": version, "enable_update": False}
    reply = client.request("/api/software/update")
    assert reply["status"] == "UNKNOWN_ERROR" and "update" in reply["error_message"]


def test_software_restart_sends_02006_resets_the_soft_estop_and_keeps_navigating(
    harness: Harness, client: Client
) -> None:
    _ok(client, "/api/estop?flag=true")
    assert client.request("/api/move?marker=lobby")["status"] == "OK"
    harness.runtime.advance(1.0)
    _ok(client, "/api/software/restart")
    note = _notification(client, "02006")
    assert (note["level"], note["description"], note["data"]) == (
        "info", "Software shutdown notice.", {})
    status = _ok(client, "/api/robot_status")
    assert status["soft_estop_state"] is False and status["move_status"] in ("canceled", "idle")
    assert harness.runtime.mode.value == "navigating" and harness.runtime.map_name == "floor1"
    assert client.request("/api/move?marker=lobby")["status"] == "OK"


# -- shutdown / reboot -------------------------------------------------------------------------


def test_shutdown_with_reboot_sends_02000_powers_off_after_10_s_and_on_5_s_later(
    harness: Harness, client: Client
) -> None:
    runtime = harness.runtime
    _ok(client, "/api/estop?flag=true")
    _ok(client, "/api/shutdown?reboot=true")
    note = _notification(client, "02000")
    assert (note["level"], note["description"], note["data"]) == (
        "info", "Poweroff notice.", {})
    assert client.request("/api/shutdown")["status"] == "REQUEST_DENIED"  # already under way
    runtime.advance(9.5)
    assert runtime.powered
    runtime.advance(1.0)
    assert not runtime.powered
    denied = client.request("/api/move?marker=lobby")
    assert (denied["status"], denied["error_message"]) == (
        "REQUEST_DENIED", "the robot is powered off")
    runtime.advance(5.0)
    assert runtime.powered
    status = _ok(client, "/api/robot_status")
    assert status["soft_estop_state"] is False  # reset by the restart
    assert runtime.map_name == "floor1"
    assert client.request("/api/move?marker=lobby")["status"] == "OK"


def test_shutdown_without_reboot_stays_off_and_bad_parameters_are_invalid(
    harness: Harness, client: Client
) -> None:
    _invalid(client, "/api/shutdown?reboot=yes", "reboot")
    _invalid(client, "/api/shutdown?reboot=true&delay=14401", "delay")
    _invalid(client, "/api/shutdown?reboot=true&delay=-1", "delay")
    _ok(client, "/api/shutdown?reboot=true&delay=1")  # back a minute and 5 s after the cut
    harness.runtime.advance(10.5 + 60.0)
    assert not harness.runtime.powered
    harness.runtime.advance(5.0)
    assert harness.runtime.powered
    _ok(client, "/api/shutdown")
    harness.runtime.advance(600.0)
    assert not harness.runtime.powered


# -- device notifications ----------------------------------------------------------------------


def test_a_robot_pushed_by_hand_sends_02005(harness: Harness, client: Client) -> None:
    _ok(client, "/api/estop?flag=true")
    harness.runtime.advance(0.5)
    harness.runtime.simulation.push(0.6)
    harness.runtime.advance(4.0)
    note = _notification(client, "02005")
    assert (note["level"], note["description"], note["data"]) == (
        "warning", "Triggered attitude correction.", {})
    # A driven robot is not "moved by hand".
    _ok(client, "/api/estop?flag=false")
    assert client.request("/api/move?marker=lobby")["status"] == "OK"
    harness.runtime.advance(20.0)
    codes = []
    while client.pushed:
        codes.append(client.pushed.pop(0).get("code"))
    assert "02005" not in codes


def test_an_object_in_the_lidar_slot_sends_03001_once(harness: Harness, client: Client) -> None:
    # A round trip first: notifications go to the connections the server has accepted, and
    # under load it may not have accepted this one yet when the fault fires.
    _ok(client, "/api/robot_status")
    harness.runtime.simulation.inject_fault("laser_slot_object")
    harness.runtime.advance(2.0)
    note = _notification(client, "03001")
    assert (note["level"], note["description"], note["data"]) == (
        "warning", "Abnormal object was detected in the robot.", {})
    _ok(client, "/api/robot_status")
    assert not [p for p in client.pushed if p.get("code") == "03001"]  # once, not per scan


COVERED: dict[str, str] = {
    "cmd 13.1 /api/wifi/list": "test_wifi_list_shows_the_networks_in_range_by_strength",
    "cmd 13.2 /api/wifi/connect": "test_wifi_connect_checks_the_password_and_remembers_it",
    "cmd 13.3 /api/wifi/get_active_connection":
        "test_wifi_connect_checks_the_password_and_remembers_it",
    "cmd 13.4 /api/wifi/info": "test_wifi_info_gives_the_address_and_the_mac",
    "cmd 13.5 /api/wifi/detail_list": "test_wifi_detail_list_describes_each_network",
    "cmd 17.1 /api/LED/set_luminance": "test_led_luminance_is_set_kept_and_checked",
    "cmd 17.2 /api/LED/set_color": "test_led_color_is_set_and_all_zero_does_not_take_effect",
    "cmd 18 /api/diagnosis/get_result":
        "test_diagnosis_reports_each_part_and_a_blocked_lidar_fails",
    "cmd 19 /api/get_power_status": "test_get_power_status_follows_the_battery_and_the_charger",
    "cmd 16.2 /api/software/check_for_update":
        "test_check_for_update_reports_the_installed_version_as_latest",
    "cmd 16.3 /api/software/update":
        "test_check_for_update_reports_the_installed_version_as_latest",
    "cmd 16.4 /api/software/restart":
        "test_software_restart_sends_02006_resets_the_soft_estop_and_keeps_navigating",
    "cmd 15 /api/shutdown":
        "test_shutdown_with_reboot_sends_02000_powers_off_after_10_s_and_on_5_s_later",
    "notify 10 02000":
        "test_shutdown_with_reboot_sends_02000_powers_off_after_10_s_and_on_5_s_later",
    "notify 10 02006":
        "test_software_restart_sends_02006_resets_the_soft_estop_and_keeps_navigating",
    "notify 10 02005": "test_a_robot_pushed_by_hand_sends_02005",
    "notify 10 03001": "test_an_object_in_the_lidar_slot_sends_03001_once",
}


def test_streams_that_need_the_robot_pause_while_it_is_off(
    harness: Harness, client: Client
) -> None:
    _ok(client, "/api/request_data?topic=human_detection&frequency=5")
    harness.runtime.advance(0.5)
    assert client.push("callback", "human_detection")["results"] == {}
    _ok(client, "/api/shutdown")
    harness.runtime.advance(10.5)
    _ok(client, "/api/robot_status")  # what was sent before the cut is read by now
    client.pushed.clear()
    harness.runtime.advance(2.0)
    _ok(client, "/api/robot_status")  # still answering: the status is the last one known
    assert not [p for p in client.pushed if p.get("topic") == "human_detection"]
