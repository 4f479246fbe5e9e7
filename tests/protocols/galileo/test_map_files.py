"""Saved maps, pictures and archives over real HTTP (galileo-http-b §5, E18–E26)."""

from __future__ import annotations

import hashlib
import io
import zipfile

from tests.protocols.galileo.conftest import Harness

COVERED = {
    "GET /api/v1/navigation/saved_maps": "test_saved_maps_lists_every_map_with_its_fields",
    "GET /api/v1/navigation/robot_tracks": "test_robot_tracks_shapes",
    "GET /api/v1/navigation/map_pgm": "test_map_pictures",
    "GET /api/v1/navigation/map_png": "test_map_pictures",
    "GET /api/v1/navigation/current_map": "test_current_map_has_name_and_md5sum",
    "GET /api/v1/navigation/upload_map": "test_dispatch_transfers_end_in_error_with_the_reason",
    "GET /api/v1/navigation/download_map": "test_dispatch_transfers_end_in_error_with_the_reason",
    "GET /api/v1/navigation/download_map_from_robot": "test_archive_round_trip",
    "POST /api/v1/navigation/upload_map_to_robot": "test_archive_round_trip",
}


def test_saved_maps_lists_every_map_with_its_fields(galileo: Harness) -> None:
    maps = galileo.ok("GET", "/navigation/saved_maps")
    assert [m["name"] for m in maps] == ["floor1", "floor2", "floor3"]
    floor2 = maps[1]
    assert list(floor2) == ["resolution", "origin", "occupied_thresh", "free_thresh", "negate",
                            "name", "md5sum", "map_type", "levels", "slam_type"]
    assert floor2["levels"] == [2] and floor2["map_type"] == "floor"
    assert floor2["origin"] == [-0.5, -0.5, 0.0] and floor2["slam_type"] == "lidar"
    assert len(floor2["md5sum"]) == 32
    assert galileo.ok("GET", "/navigation/saved_maps", params={"name": "nomap"}) == []
    assert galileo.ok("GET", "/navigation/saved_maps", params={"type": "camera"}) == []
    assert galileo.get("/navigation/saved_maps", type="sonar").status_code == 400


def test_robot_tracks_shapes(galileo: Harness) -> None:
    assert galileo.ok("GET", "/navigation/robot_tracks", params={"map_name": "floor1"}) == {
        "trajectory": []}
    assert galileo.ok("GET", "/navigation/robot_tracks") == [
        {"map_name": name, "track": []} for name in ("floor1", "floor2", "floor3")]
    assert galileo.get("/navigation/robot_tracks", map_name="nomap").status_code == 404


def test_map_pictures(galileo: Harness) -> None:
    pgm = galileo.get("/navigation/map_pgm", name="floor1")
    assert pgm.status_code == 200 and pgm.content.startswith(b"P5")
    assert b"820 500" in pgm.content[:40]
    png = galileo.get("/navigation/map_png", name="floor1")
    assert png.headers["content-type"] == "image/png" and png.content[:4] == b"\x89PNG"
    assert galileo.get("/navigation/map_png", name="nomap").status_code == 404
    assert galileo.get("/navigation/map_pgm").status_code == 400


def test_current_map_has_name_and_md5sum(galileo: Harness) -> None:
    body = galileo.ok("GET", "/navigation/current_map")
    png = galileo.get("/navigation/map_png", name="floor1").content
    assert body == {"name": "floor1", "md5sum": hashlib.md5(png).hexdigest()}


def test_dispatch_transfers_end_in_error_with_the_reason(galileo: Harness) -> None:
    up = galileo.ok("GET", "/navigation/upload_map", params={"server_id": "s1"})
    assert up["name"] == "upload_map" and up["state"] == "ERROR"
    action = up["sub_tasks"][0]
    assert action["type"] == "upload_map_action" and action["server_id"] == "s1"
    assert "dispatch" in action["result"]
    down = galileo.ok("GET", "/navigation/download_map",
                      params={"server_id": "s1", "map_id": "m1"})
    assert down["sub_tasks"][0]["map_id"] == "m1" and down["state"] == "ERROR"
    assert galileo.get("/navigation/download_map", server_id="s1").status_code == 400


def test_archive_round_trip(galileo: Harness) -> None:
    galileo.ok("POST", "/navigation/nav_points", json={
        "map_name": "floor1", "path_name": "p", "path_data": "5 10 0 1.5 0.1 0.1 0\n"})
    galileo.ok("POST", "/navigation/virtual_wall", json={
        "map_name": "floor1", "path_name": "p", "virtual_wall": "10 12\n10.05 12\n"})
    response = galileo.get("/navigation/download_map_from_robot", map_name="floor1")
    assert response.headers["content-type"] == "application/zip"
    data = response.content
    assert set(zipfile.ZipFile(io.BytesIO(data)).namelist()) == {"map.yaml", "map.png",
                                                                "galileo.json"}
    upload = galileo.http.post("/api/v1/navigation/upload_map_to_robot",
                               data={"map_name": "copy"},
                               files={"map_files": ("floor1.zip", data, "application/zip")})
    assert upload.status_code == 200 and upload.json() == {"status": "ok"}
    store = galileo.runtime.store
    assert store.load_map("copy").info == store.load_map("floor1").info
    assert galileo.ok("GET", "/navigation/path", params={"map_name": "copy"}) == ["default", "p"]
    assert galileo.ok("GET", "/navigation/nav_points", params={
        "map_name": "copy", "path_name": "p"})["path_data"] == "5 10 0 1.5 0.1 0.1 0 p_0\n"
    assert galileo.ok("GET", "/navigation/virtual_wall", params={
        "map_name": "copy", "path_name": "p"})["virtual_wall"] == "10 12\n10.05 12\n"
    before = [m.name for m in store.maps()]
    for files in ({"map_files": ("x.zip", b"not a zip", "application/zip")}, {}):
        bad = galileo.http.post("/api/v1/navigation/upload_map_to_robot",
                                data={"map_name": "bad"}, files=files)
        assert bad.status_code == 400, bad.text
    evil = io.BytesIO()
    with zipfile.ZipFile(evil, "w") as zf:
        zf.writestr("../map.yaml", "image: /etc/passwd\n")
    bad = galileo.http.post("/api/v1/navigation/upload_map_to_robot", data={"map_name": "bad"},
                            files={"map_files": ("e.zip", evil.getvalue(), "application/zip")})
    assert bad.status_code == 400
    assert [m.name for m in store.maps()] == before
    assert galileo.get("/navigation/download_map_from_robot",
                       map_name="nomap").status_code == 404
