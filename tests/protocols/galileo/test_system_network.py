"""Network and follow modes over real HTTP (galileo-http-a E-50, E-53, E-54, E-57, E-70, E-71,
E-74)."""

from __future__ import annotations

from tests.protocols.galileo.conftest import Harness

COVERED = {
    "GET /api/v1/system/wifi": "test_joining_wifi_puts_the_robot_online",
    "GET /api/v1/system/is_online": "test_joining_wifi_puts_the_robot_online",
    "GET /api/v1/system/restart_router": "test_restart_router_needs_a_network_and_checks_input",
    "GET /api/v1/system/tracking_mode": "test_follow_modes_are_switched",
    "PUT /api/v1/system/tracking_mode": "test_follow_modes_are_switched",
    "GET /api/v1/system/uwb_track": "test_follow_modes_are_switched",
    "PUT /api/v1/system/uwb_track": "test_follow_modes_are_switched",
}


def test_joining_wifi_puts_the_robot_online(galileo: Harness) -> None:
    assert galileo.ok("GET", "/system/is_online") == {"result": False}
    wrong = galileo.get("/system/wifi", ssid="polynav-office", password="guess")
    assert wrong.status_code == 400 and "wrong password" in wrong.json()["status"]
    far = galileo.get("/system/wifi", ssid="elsewhere", password="x")
    assert far.status_code == 400 and "in range" in far.json()["status"]
    assert galileo.get("/system/wifi", ssid="polynav-office").status_code == 400
    assert galileo.ok("GET", "/system/is_online") == {"result": False}
    assert galileo.ok("GET", "/system/wifi", params={"ssid": "polynav-office",
                                                     "password": "office-2437"}) == {
        "status": "ok"}
    assert galileo.ok("GET", "/system/is_online") == {"result": True}


def test_restart_router_needs_a_network_and_checks_input(galileo: Harness) -> None:
    good = {"ip": "192.168.0.1", "username": "admin", "password": "pw"}
    offline = galileo.get("/system/restart_router", **good)
    assert offline.status_code == 409
    galileo.ok("GET", "/system/wifi", params={"ssid": "polynav-office",
                                              "password": "office-2437"})
    assert galileo.ok("GET", "/system/restart_router", params=good) == {"status": "ok"}
    assert galileo.ok("GET", "/system/restart_router", params={**good, "type": "tplink"}) == {
        "status": "ok"}
    for bad in ({**good, "type": "netgear"}, {**good, "ip": "router"},
                {"ip": "192.168.0.1", "username": "admin"}):
        assert galileo.get("/system/restart_router", **bad).status_code == 400, bad


def test_follow_modes_are_switched(galileo: Harness) -> None:
    assert galileo.ok("GET", "/system/tracking_mode") == {"tracking_flag": False}
    assert galileo.ok("PUT", "/system/tracking_mode", json={"enable": True}) == {
        "tracking_flag": True}
    assert galileo.ok("GET", "/system/tracking_mode") == {"tracking_flag": True}
    assert galileo.ok("GET", "/system/uwb_track") == {"enable": False}
    assert galileo.ok("PUT", "/system/uwb_track", json={"enable": True}) == {"status": "ok"}
    assert galileo.ok("GET", "/system/uwb_track") == {"enable": True}
    assert galileo.put("/system/uwb_track", {"enable": "yes please"}).status_code == 400
    assert galileo.put("/system/tracking_mode", {}).status_code == 400
    assert galileo.ok("GET", "/system/uwb_track") == {"enable": True}
