"""Mapping endpoints over real HTTP (galileo-http-b §3, E1–E8) on the runtime's mapping mode."""

from __future__ import annotations

from tests.protocols.galileo.conftest import Harness

COVERED = {
    "GET /api/v1/map/start": "test_map_then_save_and_stop",
    "GET /api/v1/map/stop": "test_map_then_save_and_stop",
    "GET /api/v1/map/pose": "test_map_then_save_and_stop",
    "GET /api/v1/map/current_map_image": "test_map_then_save_and_stop",
    "POST /api/v1/map/current_map_image": "test_map_then_save_and_stop",
    "GET /api/v1/map/current_map_png": "test_map_then_save_and_stop",
    "GET /api/v1/map/track": "test_map_then_save_and_stop",
    "GET /api/v1/map/update": "test_map_update_extends_the_map_navigated_on",
}


def _drive(g: Harness, seconds: float, angular: float = 0.0) -> None:
    steps = int(seconds / 0.2)
    for _ in range(steps):
        g.runtime.teleop(0.3, angular)
        g.runtime.advance(0.2)


def test_map_then_save_and_stop(galileo: Harness) -> None:
    assert galileo.get("/map/pose").status_code == 409
    assert galileo.ok("GET", "/map/start") == {"result": True}
    galileo.runtime.advance(0.5)
    assert galileo.ok("GET", "/system/status") == {"status": "Mapping"}
    assert galileo.ok("GET", "/system/galileo_status")["mapStatus"] == 1
    assert galileo.ok("GET", "/map/start")["result"] is False  # already mapping
    assert galileo.ok("GET", "/map/track") == {"trajectory": []}
    _drive(galileo, 3.0)
    pose = galileo.ok("GET", "/map/pose")
    assert set(pose) == {"x", "y", "angle"} and pose["x"] > 0.5
    info = galileo.ok("GET", "/map/current_map_image")
    assert info["status"] == "OK" and info["map_image"] == "/api/v1/map/current_map_png"
    assert len(info["map_params"]["origin"]) == 3 and info["map_params"]["width"] > 10
    png = galileo.get("/map/current_map_png")
    assert png.headers["content-type"] == "image/png" and png.content[:4] == b"\x89PNG"
    saved = galileo.ok("POST", "/map/current_map_image",
                       json={"name": "lab", "type": "floor", "levels": [3]})
    assert saved == {"result": True, "name": "lab"}
    track = galileo.ok("GET", "/map/track")["trajectory"]
    assert len(track) > 3 and set(track[0]) == {"x", "y", "z"}
    bad = galileo.ok("POST", "/map/current_map_image", json={"name": "x", "type": "boat"})
    assert bad["result"] is False and "type" in bad["description"]
    _drive(galileo, 1.0)
    assert galileo.ok("GET", "/map/stop") == {"result": True}
    assert galileo.ok("GET", "/system/status") == {"status": "Free"}
    maps = galileo.ok("GET", "/navigation/saved_maps", params={"name": "lab"})
    assert maps[0]["levels"] == [3] and maps[0]["map_type"] == "floor"
    assert galileo.ok("GET", "/map/stop")["result"] is False  # not mapping


def test_map_stop_without_a_save_keeps_the_working_map(galileo: Harness) -> None:
    galileo.ok("GET", "/map/start")
    _drive(galileo, 1.0)
    assert galileo.ok("GET", "/map/stop") == {"result": True}
    assert [m["name"] for m in galileo.ok("GET", "/navigation/saved_maps",
                                          params={"name": "slamdb"})] == ["slamdb"]


def test_map_update_extends_the_map_navigated_on(galileo: Harness) -> None:
    before = galileo.runtime.store.map_record("floor1")
    points = {p.name for p in galileo.runtime.store.points(map_name="floor1")}
    galileo.ok("GET", "/navigation/start", params={"map": "floor1"})
    galileo.runtime.advance(1.0)
    assert galileo.ok("GET", "/map/update") == {"result": True}  # the map navigated on
    assert galileo.ok("GET", "/system/status") == {"status": "Mapping"}
    assert galileo.ok("GET", "/map/update")["result"] is False  # already mapping
    _drive(galileo, 2.0)
    assert galileo.ok("GET", "/map/stop") == {"result": True}
    assert galileo.ok("GET", "/system/status") == {"status": "Free"}
    after = galileo.runtime.store.map_record("floor1")
    assert (after.floor, after.resolution) == (before.floor, before.resolution)
    assert {p.name for p in galileo.runtime.store.points(map_name="floor1")} == points
    assert [m["name"] for m in galileo.ok("GET", "/navigation/saved_maps",
                                          params={"name": "slamdb"})] == []
    assert galileo.ok("GET", "/navigation/start", params={"map": "floor1"})["result"] is True


def test_map_update_from_a_target_point(galileo: Harness) -> None:
    galileo.ok("GET", "/navigation/start", params={"map": "floor1"})
    galileo.runtime.advance(1.0)
    galileo.ok("GET", "/navigation/stop")
    body = galileo.ok("GET", "/map/update", params={"map": "floor1", "start_index": 0})
    assert body == {"result": True}
    galileo.runtime.advance(0.5)
    assert galileo.ok("GET", "/system/galileo_status")["mapStatus"] == 1
    assert galileo.ok("GET", "/map/stop") == {"result": True}


def test_map_update_refusals_change_nothing(galileo: Harness) -> None:
    for params in ({"map": "nomap"}, {"map": "floor1", "start_index": 999},
                   {"map": "floor1", "path": "nopath", "start_index": 0},
                   {"map": "floor1", "start_index": "first"}):
        body = galileo.ok("GET", "/map/update", params=params)
        assert body["result"] is False and body["description"], params
        assert galileo.runtime.status().mode == "free"
