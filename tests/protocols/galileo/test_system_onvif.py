"""ONVIF cameras over real HTTP (galileo-http-a E-77–E-85)."""

from __future__ import annotations

from typing import Any

import pytest

from tests.protocols.galileo.conftest import Harness

COVERED = {
    "GET /api/v1/system/onvif_cameras @2332-2360": "test_the_camera_is_listed_and_its_profiles",
    "GET /api/v1/system/onvif_cameras @2362-2562": "test_the_camera_is_listed_and_its_profiles",
    "GET /api/v1/system/onvif_camera/stream": "test_the_stream_address_names_the_channel",
    "GET /api/v1/system/onvif_camera/move": "test_the_head_moves_on_the_clock",
    "GET /api/v1/system/onvif_camera/pose": "test_the_head_moves_on_the_clock",
    "GET /api/v1/system/onvif_camera/goto_preset": "test_presets_and_speed_moves",
    "GET /api/v1/system/onvif_camera/move_speed": "test_presets_and_speed_moves",
    "GET /api/v1/system/onvif_camera/snapshot": "test_a_snapshot_is_a_file_the_file_api_serves",
    "GET /api/v1/system/onvif_camera/temperature": "test_temperature_follows_the_room",
}

CAMERA = {"ip": "192.0.2.64", "port": 80, "username": "admin", "password": "polynav"}


def _get(g: Harness, path: str, **extra: Any) -> Any:
    return g.ok("GET", path, params={**CAMERA, **extra})


def test_the_camera_is_listed_and_its_profiles(galileo: Harness) -> None:
    assert galileo.ok("GET", "/system/onvif_cameras") == [{"ip": "192.0.2.64", "port": 80}]
    reply = galileo.get("/system/onvif_cameras", **CAMERA)
    assert reply.status_code == 200 and reply.headers["content-type"].startswith("text/plain")
    assert reply.text.startswith("[{'Name': 'Stream_101'")
    assert "'token': 'Profile_101'" in reply.text
    wrong = galileo.get("/system/onvif_cameras", **{**CAMERA, "password": "guess"})
    assert wrong.status_code == 400 and "refused" in wrong.json()["description"]


def test_the_stream_address_names_the_channel(galileo: Harness) -> None:
    assert _get(galileo, "/system/onvif_camera/stream") == {
        "stream": "rtsp://admin:polynav@192.0.2.64:554/Streaming/Channels/101"
                  "?transportmode=unicast&profile=Profile_101"}
    assert galileo.get("/system/onvif_camera/stream", **CAMERA, channel=2).status_code == 400


def test_the_head_moves_on_the_clock(galileo: Harness) -> None:
    assert _get(galileo, "/system/onvif_camera/pose") == {"x": 0.0, "y": 0.0, "zoom": 0.0}
    body = _get(galileo, "/system/onvif_camera/move", x=0.5, y=-0.25, zoom=1.0)
    assert body["status"] == "ok" and isinstance(body["description"], str)
    galileo.runtime.advance(0.5)
    mid = _get(galileo, "/system/onvif_camera/pose")
    assert 0.0 < mid["x"] < 0.5 and 0.0 < mid["zoom"] < 1.0
    galileo.runtime.advance(2.0)
    assert _get(galileo, "/system/onvif_camera/pose") == {"x": 0.5, "y": -0.25, "zoom": 1.0}
    for bad in ({"x": 2.0, "y": 0, "zoom": 0}, {"x": 0, "y": 0}, {"x": "left", "y": 0,
                                                                    "zoom": 0}):
        assert galileo.get("/system/onvif_camera/move", **CAMERA, **bad).status_code == 400
    # Without the camera's name or credentials nothing moves.
    assert galileo.get("/system/onvif_camera/move", x=0, y=0, zoom=0).status_code == 400
    galileo.runtime.advance(2.0)
    assert _get(galileo, "/system/onvif_camera/pose") == {"x": 0.5, "y": -0.25, "zoom": 1.0}


def test_presets_and_speed_moves(galileo: Harness) -> None:
    assert _get(galileo, "/system/onvif_camera/goto_preset", preset="left") == {"status": "ok"}
    galileo.runtime.advance(2.0)
    assert _get(galileo, "/system/onvif_camera/pose")["x"] == 0.5
    assert galileo.get("/system/onvif_camera/goto_preset", **CAMERA,
                       preset="nowhere").status_code == 400
    body = _get(galileo, "/system/onvif_camera/move_speed", speed_x=-0.2, speed_y=0,
                speed_zoom=0)
    assert body["status"] == "success"
    galileo.runtime.advance(1.0)
    assert _get(galileo, "/system/onvif_camera/pose")["x"] == pytest.approx(0.3)
    _get(galileo, "/system/onvif_camera/move_speed", speed_x=0, speed_y=0, speed_zoom=0)
    galileo.runtime.advance(1.0)
    assert _get(galileo, "/system/onvif_camera/pose")["x"] == pytest.approx(0.3)


def test_a_snapshot_is_a_file_the_file_api_serves(galileo: Harness) -> None:
    path = _get(galileo, "/system/onvif_camera/snapshot")["snapshot"]
    assert path.startswith("/home/xiaoqiang/Pictures/") and path.endswith(".jpg")
    image = galileo.get("/fs/file_api", path=path)
    assert image.status_code == 200 and image.content[:2] == b"\xff\xd8"
    assert image.headers["content-type"] == "image/jpeg"


def test_temperature_follows_the_room(galileo: Harness) -> None:
    body = _get(galileo, "/system/onvif_camera/temperature")
    rules = body["temperature"]["ThermometryRulesTemperatureInfoList"][
        "ThermometryRulesTemperatureInfo"]
    assert [r["id"] for r in rules] == [1, 2]
    env = galileo.ok("GET", "/system/topic",
                     params={"topic_name": "/bw_env_sensors/EnvSensorData"})
    for rule in rules:
        assert rule["minTemperature"] <= rule["averageTemperature"] <= rule["maxTemperature"]
        assert abs(rule["averageTemperature"] - env["temperature"]) < 0.1
        assert set(rule["MaxTemperaturePoint"]) == {"positionX", "positionY"}
        assert rule["isFreezedata"] is False
