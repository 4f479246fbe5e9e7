"""Paths and target points over real HTTP (galileo-http-b §7–8), and the same points seen
through the native store view (one store, several views)."""

from __future__ import annotations

from polynav.site import PointKind
from tests.protocols.galileo.conftest import Harness

COVERED = {
    "GET /api/v1/navigation/path": "test_path_listing_has_default_paths_and_uploaded_ones",
    "POST /api/v1/navigation/path": "test_path_upload_is_stored_verbatim_and_overwrites",
    "PUT /api/v1/navigation/path": "test_path_upload_is_stored_verbatim_and_overwrites",
    "DELETE /api/v1/navigation/path": "test_delete_path_deletes_its_target_points",
    "GET /api/v1/navigation/nav_points": "test_default_path_target_points_are_the_named_points",
    "POST /api/v1/navigation/nav_points": "test_uploaded_target_points_are_map_points",
    "PUT /api/v1/navigation/nav_points": "test_uploaded_target_points_are_map_points",
    "DELETE /api/v1/navigation/nav_points": "test_delete_nav_points_keeps_the_path",
}

PATH = "0.575 -0.356 0\n6.98246 17.95874 0\n9.969936\t15.64437 0\n"
TARGETS = "5.0 10.0 0 1.5 0.1 0.1 0\n8.0 12.4 0 -0.5 0.2 0.2 1 gate A\n"


def test_default_path_target_points_are_the_named_points(galileo: Harness) -> None:
    body = galileo.ok("GET", "/navigation/nav_points",
                      params={"map_name": "floor1", "path_name": "default"})
    lines = body["path_data"].splitlines()
    assert lines[0] == "8 8.5 0 0 0.1 0.1 0 initial"
    assert lines[1] == "5.5 12.5 0 0 0.1 0.1 0 lobby"
    names = [line.split(maxsplit=7)[7] for line in lines]
    assert "charger" not in names  # the charge pile is index -1
    store_names = [p.name for p in galileo.runtime.store.points(map_name="floor1")
                   if p.kind is not PointKind.CHARGER]
    assert names == store_names
    # Without parameters: the map and path in use (floor1 / default before any start).
    assert galileo.ok("GET", "/navigation/nav_points") == body
    assert galileo.get("/navigation/nav_points", map_name="nomap").status_code == 404


def test_path_listing_has_default_paths_and_uploaded_ones(galileo: Harness) -> None:
    assert galileo.ok("GET", "/navigation/path") == {"floor1": ["default"],
                                                     "floor2": ["default"],
                                                     "floor3": ["default"]}
    galileo.ok("POST", "/navigation/path",
               json={"map_name": "floor2", "path_name": "route \u673a", "path_data": PATH})
    assert galileo.ok("GET", "/navigation/path", params={"map_name": "floor2"}) == [
        "default", "route \u673a"]
    raw = galileo.get("/navigation/path", map_name="floor2").content
    assert "\u673a".encode() in raw or b"\\u673a" in raw
    default = galileo.ok("GET", "/navigation/path",
                         params={"map_name": "floor1", "path_name": "default"})
    assert default["path_data"].startswith("8 8.5 0\n5.5 12.5 0\n")
    assert galileo.get("/navigation/path", map_name="floor1",
                       path_name="nopath").status_code == 404


def test_path_upload_is_stored_verbatim_and_overwrites(galileo: Harness) -> None:
    body = {"map_name": "floor1", "path_name": "p1", "path_data": PATH}
    assert galileo.ok("POST", "/navigation/path", json=body) == body
    got = galileo.ok("GET", "/navigation/path", params={"map_name": "floor1", "path_name": "p1"})
    assert got == body
    second = {**body, "path_data": "1 2 0\n"}
    assert galileo.ok("PUT", "/navigation/path", json=second) == second
    assert galileo.ok("GET", "/navigation/path",
                      params={"map_name": "floor1", "path_name": "p1"})["path_data"] == "1 2 0\n"
    before = galileo.runtime.store.routes("floor1")
    for bad in ({**body, "path_data": "1 2 3 4\n"}, {**body, "path_data": "a b c\n"},
                {**body, "path_data": 5}, {**body, "map_name": "nomap"},
                {"map_name": "floor1", "path_name": "p1"}, {**body, "path_name": " p"}):
        response = galileo.post("/navigation/path", bad)
        assert response.status_code in (400, 404), (bad, response.text)
        assert response.json()["status"] == "error"
    assert galileo.runtime.store.routes("floor1") == before


def test_uploaded_target_points_are_map_points(galileo: Harness) -> None:
    body = {"map_name": "floor1", "path_name": "p1", "path_data": TARGETS}
    assert galileo.ok("POST", "/navigation/nav_points", json=body) == body
    store = galileo.runtime.store
    unnamed = store.point("floor1", "p1_0")
    assert (unnamed.pose.x, unnamed.pose.y, unnamed.pose.theta) == (5.0, 10.0, 1.5)
    assert store.point("floor1", "gate A").pose.theta == -0.5
    got = galileo.ok("GET", "/navigation/nav_points",
                     params={"map_name": "floor1", "path_name": "p1"})
    assert got["path_data"] == "5 10 0 1.5 0.1 0.1 0\n8 12.4 0 -0.5 0.2 0.2 1 gate A\n"
    # PUT replaces: the point created for line 0 and no longer used is deleted.
    galileo.ok("PUT", "/navigation/nav_points",
               json={**body, "path_data": "8 12.4 0 0 0.1 0.1 0 gate A\n"})
    assert [p.name for p in store.points(map_name="floor1")].count("p1_0") == 0
    # A named line reuses the map's point of that name (moved there).
    galileo.ok("PUT", "/navigation/nav_points",
               json={**body, "path_data": "5.6 12.4 0 0 0.1 0.1 0 lobby\n"})
    assert store.point("floor1", "lobby").pose.x == 5.6
    before = store.points(map_name="floor1")
    for bad in ("1 2 3\n", "1 2 0 0 0.1 0.1 x\n", "1 2 0 0 -1 0.1 0\n", "1 2 0 nan 0.1 0.1 0\n",
                "1 2 0 0 0.1 0.1 0 a\n3 4 0 0 0.1 0.1 0 a\n"):
        response = galileo.post("/navigation/nav_points", {**body, "path_data": bad})
        assert response.status_code == 400, (bad, response.text)
    assert store.points(map_name="floor1") == before


def test_nav_points_default_to_the_map_and_path_in_use(galileo: Harness) -> None:
    galileo.ok("POST", "/navigation/nav_points",
               json={"map_name": "floor1", "path_name": "p2", "path_data": TARGETS})
    galileo.ok("GET", "/navigation/start", params={"map": "floor1", "path": "p2",
                                                    "start_index": 1})
    galileo.runtime.advance(1.0)
    assert galileo.ok("GET", "/navigation/nav_points")["path_name"] == "p2"
    galileo.ok("POST", "/navigation/nav_points", json={"path_data": "9 12.4 0 0 0.1 0.1 0\n"})
    assert galileo.runtime.store.point("floor1", "p2_0").pose.x == 9.0


def test_delete_nav_points_keeps_the_path(galileo: Harness) -> None:
    body = {"map_name": "floor1", "path_name": "p1"}
    galileo.ok("POST", "/navigation/path", json={**body, "path_data": PATH})
    galileo.ok("POST", "/navigation/nav_points", json={**body, "path_data": TARGETS})
    assert galileo.ok("DELETE", "/navigation/nav_points", params=body) == {"status": "ok"}
    assert galileo.ok("GET", "/navigation/nav_points", params=body)["path_data"] == ""
    assert galileo.ok("GET", "/navigation/path", params=body)["path_data"] == PATH
    names = [p.name for p in galileo.runtime.store.points(map_name="floor1")]
    assert "p1_0" not in names and "gate A" not in names
    assert galileo.delete("/navigation/nav_points", map_name="floor1").status_code == 400


def test_delete_path_deletes_its_target_points(galileo: Harness) -> None:
    body = {"map_name": "floor1", "path_name": "p1"}
    galileo.ok("POST", "/navigation/path", json={**body, "path_data": PATH})
    galileo.ok("POST", "/navigation/nav_points", json={**body, "path_data": TARGETS})
    assert galileo.ok("DELETE", "/navigation/path", params=body) == {"status": "ok"}
    assert galileo.ok("GET", "/navigation/path", params={"map_name": "floor1"}) == ["default"]
    assert "p1_0" not in [p.name for p in galileo.runtime.store.points(map_name="floor1")]
    assert galileo.delete("/navigation/path", **body).status_code == 404
    assert galileo.delete("/navigation/path", map_name="floor1",
                          path_name="default").status_code == 404
