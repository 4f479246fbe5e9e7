"""Map operations (puwei-api §6) and ``POST /api/map/upload`` (issue 33 item 2)."""

from __future__ import annotations

import io

import yaml
from PIL import Image

from tests.protocols.puwei.conftest import MAP, Harness, envelope, refused

COVERED = {
    "GET /api/map/save/:name": "test_save_while_mapping_adds_the_map",
    "GET /api/map/list": "test_list_has_the_documented_fields_for_every_map",
    "GET /api/map/delete/:name": "test_delete_removes_the_map",
    "GET /api/map/download/:name": "test_download_png_and_yaml_as_documented",
    "POST /api/map/upload": "test_upload_of_a_downloaded_pair_makes_the_same_map",
}


def names(puwei: Harness) -> list[str]:
    return [m["name"] for m in puwei.ok("/api/map/list")]


def test_list_has_the_documented_fields_for_every_map(puwei: Harness) -> None:
    maps = puwei.ok("/api/map/list")
    assert [m["name"] for m in maps] == ["floor1", "floor2", "floor3"]
    for number, item in enumerate(maps, start=1):
        assert set(item) == {"id", "name", "path", "points", "create_at", "update_at"}
        assert item["id"] == number
        assert item["path"] == f"/api/map/download/{item['name']}.png"
        assert isinstance(item["points"], str) and isinstance(item["create_at"], str)
        assert len(item["update_at"]) == len("2026-01-07 09:00:00")
    assert maps[0]["points"] == str(len(puwei.runtime.store.points(map_name="floor1")))


def test_save_while_mapping_adds_the_map(puwei: Harness) -> None:
    assert refused(puwei.get("/api/map/save/lab"))["code"] == 4  # not mapping
    puwei.ok("/api/roslaunch/mapping")
    puwei.runtime.advance(1.0)
    assert puwei.ok("/api/map/save/lab") is None
    assert "lab" in names(puwei)
    assert puwei.runtime.status().mode == "mapping"  # mapping goes on


def test_delete_removes_the_map(puwei: Harness) -> None:
    store = puwei.runtime.store
    store.save_map("spare", store.load_map("floor3"))
    assert puwei.ok("/api/map/delete/spare") is None
    assert names(puwei) == ["floor1", "floor2", "floor3"]
    assert refused(puwei.get("/api/map/delete/spare"))["code"] == 3
    # A floor's own map: refused by the store, nothing deleted.
    assert refused(puwei.get("/api/map/delete/floor3"))["code"] == 4
    assert names(puwei) == ["floor1", "floor2", "floor3"]


def test_delete_of_the_map_navigated_on_is_refused(puwei: Harness) -> None:
    puwei.navigate()
    assert refused(puwei.get(f"/api/map/delete/{MAP}"))["code"] == 4
    assert MAP in names(puwei)


def test_download_png_and_yaml_as_documented(puwei: Harness) -> None:
    png = puwei.get(f"/api/map/download/{MAP}.png")
    assert png.status_code == 200 and png.headers["content-type"] == "image/png"
    picture = Image.open(io.BytesIO(png.content))
    record = puwei.runtime.store.map_record(MAP)
    assert picture.size == (record.width, record.height)
    text = puwei.get(f"/api/map/download/{MAP}.yaml").text
    lines = text.splitlines()
    assert lines[0] == f"image: {MAP}.png"
    assert lines[1] == f"resolution: {record.resolution:.6f}"
    o = record.origin
    assert lines[2] == f"origin: [{o.x:.6f}, {o.y:.6f}, {o.theta:.6f}]"
    assert lines[3:6] == ["negate: 0", "occupied_thresh: 0.65", "free_thresh: 0.196"]
    assert yaml.safe_load(text)["origin"] == [round(o.x, 6), round(o.y, 6), round(o.theta, 6)]


def test_download_of_an_unknown_map_or_suffix_is_a_json_error(puwei: Harness) -> None:
    assert refused(puwei.get("/api/map/download/nowhere.png"))["code"] == 3
    assert refused(puwei.get("/api/map/download/nowhere.yaml"))["code"] == 3
    assert refused(puwei.get(f"/api/map/download/{MAP}.pgm"))["code"] == 2
    assert refused(puwei.get(f"/api/map/download/{MAP}"))["code"] == 2


def test_upload_of_a_downloaded_pair_makes_the_same_map(puwei: Harness) -> None:
    png = puwei.get(f"/api/map/download/{MAP}.png").content
    text = puwei.get(f"/api/map/download/{MAP}.yaml").content
    files = {"png": ("copy.png", png, "image/png"), "yaml": ("copy.yaml", text, "text/yaml")}
    body = envelope(puwei.http.post("/api/map/upload", files=files, headers=puwei.headers()))
    assert body["code"] == 0, body
    assert "copy" in names(puwei)
    original = puwei.runtime.store.load_map(MAP)
    copy = puwei.runtime.store.load_map("copy")
    assert (copy.data == original.data).all()
    assert copy.info.origin.x == round(original.info.origin.x, 6)
    # The same name again: refused unless overwrite=true.
    again = puwei.http.post("/api/map/upload", files=files, headers=puwei.headers())
    assert refused(again)["code"] == 4
    replaced = puwei.http.post("/api/map/upload?overwrite=true", files=files,
                               headers=puwei.headers())
    assert envelope(replaced)["code"] == 0


def test_upload_of_bad_files_is_refused_and_makes_no_map(puwei: Harness) -> None:
    headers = puwei.headers()
    cases = [
        {"png": ("x.png", b"not a png", "image/png"), "yaml": ("x.yaml", b"resolution: 0.05\n"
                                                                 b"origin: [0, 0, 0]\n", "t")},
        {"png": ("x.png", b"", "image/png")},
        {"png": ("x.png", b"", "image/png"), "yaml": ("x.yaml", b": : [", "t")},
    ]
    for files in cases:
        assert refused(puwei.http.post("/api/map/upload", files=files,
                                       headers=headers))["code"] == 2
    assert refused(puwei.post("/api/map/upload", {"name": "x"}))["code"] == 2
    assert names(puwei) == ["floor1", "floor2", "floor3"]
