"""Wind sensor and landmarks over real HTTP (galileo-http-b E63, E64)."""

from __future__ import annotations

from tests.protocols.galileo.conftest import Harness

COVERED = {
    "GET /api/v1/navigation/wind_info": "test_wind_info_reads_no_sensor",
    "GET /api/v1/navigation/landmarks": "test_landmarks_per_map",
}


def test_wind_info_reads_no_sensor(galileo: Harness) -> None:
    assert galileo.ok("GET", "/navigation/wind_info") == {
        "current_speed": -1.0, "max_speed": -1.0, "level": -1.0, "direction": -1.0}


def test_landmarks_per_map(galileo: Harness) -> None:
    assert galileo.ok("GET", "/navigation/landmarks", params={"map_name": "floor2"}) == {
        "map_name": "floor2", "landmarks": []}
    assert galileo.ok("GET", "/navigation/landmarks") == [
        {"map_name": name, "landmarks": []} for name in ("floor1", "floor2", "floor3")]
    assert galileo.get("/navigation/landmarks", map_name="nomap").status_code == 404
