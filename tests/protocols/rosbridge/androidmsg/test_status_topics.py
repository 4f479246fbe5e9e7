"""The status topics over the wire, latched, with the spec's codes."""

from __future__ import annotations

from tests.protocols.rosbridge.androidmsg.conftest import Robot

COVERED = {
    "/androidmsg_initstatus": "test_init_power_and_map_status_are_latched",
    "/power_report": "test_init_power_and_map_status_are_latched",
    "/map_status": "test_map_status_follows_mapping",
    "/androidmsg_emergencystatus": "test_emergency_status_follows_the_estop",
    "/androidmsg_chargestatus": "test_charge_status_is_41_when_not_charging",
    "/androidmsg_locationstatus": "test_location_status_says_localized",
    "/androidmsg_mapstatus": "test_map_load_status_is_60_when_a_map_loads",
}


def test_init_power_and_map_status_are_latched(robot: Robot) -> None:
    for topic in ("/androidmsg_initstatus", "/power_report", "/map_status"):
        robot.subscribe(topic)
    assert robot.codes("/androidmsg_initstatus", lambda c: bool(c), 1) == [12]
    power = robot.codes("/power_report", lambda c: bool(c), 1)[0]
    assert power == round(robot.runtime.status().battery_percent)
    assert robot.codes("/map_status", lambda c: bool(c), 1) == [0]


def test_map_status_follows_mapping(robot: Robot) -> None:
    robot.subscribe("/map_status")
    robot.call("/clear_map")
    assert robot.codes("/map_status", lambda c: 1 in c, 2) == [0, 1]


def test_emergency_status_follows_the_estop(robot: Robot) -> None:
    robot.subscribe("/androidmsg_emergencystatus")
    assert robot.codes("/androidmsg_emergencystatus", lambda c: bool(c), 1) == [32]
    robot.runtime.set_software_estop(True)
    assert robot.codes("/androidmsg_emergencystatus", lambda c: 31 in c, 1) == [32, 31]
    robot.runtime.set_software_estop(False)
    assert robot.codes("/androidmsg_emergencystatus", lambda c: len(c) == 3, 1) == [32, 31, 32]


def test_charge_status_is_41_when_not_charging(robot: Robot) -> None:
    robot.subscribe("/androidmsg_chargestatus")
    assert robot.codes("/androidmsg_chargestatus", lambda c: bool(c), 1) == [41]


def test_location_status_says_localized(robot: Robot) -> None:
    robot.subscribe("/androidmsg_locationstatus")
    robot.runtime.start_navigation("floor1", point="initial")
    assert robot.codes("/androidmsg_locationstatus", lambda c: 10 in c, 5)[-1] == 10


def test_map_load_status_is_60_when_a_map_loads(robot: Robot) -> None:
    robot.subscribe("/androidmsg_mapstatus")
    robot.runtime.start_navigation("floor1", point="initial")
    assert robot.codes("/androidmsg_mapstatus", lambda c: 60 in c, 5) == [60]
