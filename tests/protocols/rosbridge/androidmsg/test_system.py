"""/set_wifi, /navi_info, /robot_ssh over the wire."""

from __future__ import annotations

import json

from tests.protocols.rosbridge.androidmsg.conftest import Robot

COVERED = {
    "/set_wifi": "test_set_wifi_joins_a_network_in_range",
    "/navi_info": "test_navi_info_is_version_json",
    "/robot_ssh": "test_robot_ssh_takes_only_its_allow_list",
}


def test_set_wifi_joins_a_network_in_range(robot: Robot) -> None:
    assert robot.call("/set_wifi", {"wifi_name": "polynav-office",
                                    "wifi_pass": "office-2437"}) == {}
    assert robot.runtime.device.network().active == "polynav-office"
    assert "password" in robot.fail("/set_wifi", {"wifi_name": "polynav-office-5G",
                                                  "wifi_pass": "wrong"}).lower()
    assert "'wifi_name'" in robot.fail("/set_wifi", {"wifi_pass": "x"})


def test_navi_info_is_version_json(robot: Robot) -> None:
    values = robot.call("/navi_info")
    info = json.loads(values["nav_info"])
    assert values["status"] == 0
    assert set(info) == {"coco_num", "navi_channel", "numero", "version_code", "version_name"}


def test_robot_ssh_takes_only_its_allow_list(robot: Robot) -> None:
    assert "not allowed" in robot.fail("/robot_ssh", {"instruction": "rm -rf /"})
    assert "not allowed" in robot.fail("/robot_ssh", {"instruction": "reboot; ls"})
    assert robot.call("/robot_ssh", {"instruction": "reboot"}) == {"status": 0,
                                                                   "data": "rebooting"}
    assert robot.wait(lambda: not robot.runtime.powered, 60)
    assert robot.wait(lambda: robot.runtime.powered, 120)  # it comes back: a reboot
