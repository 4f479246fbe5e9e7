"""Ignore areas and virtual walls over real HTTP (galileo-http-b §10): stored per (map, path),
mirrored into the map's keepouts, and lethal in the costmap when navigation starts."""

from __future__ import annotations

from polynav.maps.costs import LETHAL
from polynav.maps.keepout import ForbiddenZone, VirtualWall
from tests.protocols.galileo.conftest import Harness

COVERED = {
    "GET /api/v1/navigation/skip_area": "test_skip_areas_round_trip_and_become_forbidden_zones",
    "POST /api/v1/navigation/skip_area": "test_skip_areas_round_trip_and_become_forbidden_zones",
    "DELETE /api/v1/navigation/skip_area": "test_skip_areas_round_trip_and_become_forbidden_zones",
    "GET /api/v1/navigation/virtual_wall": "test_virtual_walls_block_the_costmap",
    "POST /api/v1/navigation/virtual_wall": "test_virtual_walls_block_the_costmap",
    "DELETE /api/v1/navigation/virtual_wall": "test_virtual_walls_block_the_costmap",
}

AREA = "9.89896392822266 19.9832229614258 12.0267267227173 20.9590129852295\n"
WALL = "".join(f"{10.0 + 0.05 * i:.2f} 12.4\n" for i in range(11))


def test_skip_areas_round_trip_and_become_forbidden_zones(galileo: Harness) -> None:
    names = {"map_name": "floor1", "path_name": "default"}
    assert galileo.ok("GET", "/navigation/skip_area", params=names)["skip_area"] == ""
    body = {**names, "skip_area": AREA}
    assert galileo.ok("POST", "/navigation/skip_area", json=body) == body
    assert galileo.ok("GET", "/navigation/skip_area", params=names) == body
    keepouts = galileo.runtime.store.keepouts("floor1")
    assert keepouts == [ForbiddenZone(((9.89896392822266, 19.9832229614258),
                                       (12.0267267227173, 19.9832229614258),
                                       (12.0267267227173, 20.9590129852295),
                                       (9.89896392822266, 20.9590129852295)))]
    # The default path keeps following the map's points after areas are stored on it.
    assert "lobby" in galileo.ok("GET", "/navigation/nav_points", params=names)["path_data"]
    for bad in ("1 2 3\n", "1 2 1 5\n", "a b c d\n"):
        assert galileo.post("/navigation/skip_area", {**names, "skip_area": bad}
                            ).status_code == 400
    assert galileo.post("/navigation/skip_area", {**body, "map_name": "x"}).status_code == 404
    assert galileo.ok("DELETE", "/navigation/skip_area", params=names) == {"status": "ok"}
    assert galileo.runtime.store.keepouts("floor1") == []
    assert galileo.ok("GET", "/navigation/skip_area", params=names)["skip_area"] == ""


def test_virtual_walls_block_the_costmap(galileo: Harness) -> None:
    names = {"map_name": "floor1", "path_name": "default"}
    body = {**names, "virtual_wall": WALL}
    assert galileo.ok("POST", "/navigation/virtual_wall", json=body) == body
    got = galileo.ok("GET", "/navigation/virtual_wall", params=names)["virtual_wall"]
    assert got.splitlines()[0] == "10 12.4" and len(got.splitlines()) == 11
    keepouts = galileo.runtime.store.keepouts("floor1")
    assert len(keepouts) == 1 and isinstance(keepouts[0], VirtualWall)
    galileo.ok("GET", "/navigation/start", params={"map": "floor1", "start_index": 1})
    galileo.runtime.advance(1.0)
    stack = galileo.runtime.navigation_stack
    assert stack is not None and stack.costmap.cost_at(10.25, 12.4) == LETHAL
    assert galileo.post("/navigation/virtual_wall", {**names, "virtual_wall": "1\n"}
                        ).status_code == 400
    assert galileo.ok("DELETE", "/navigation/virtual_wall", params=names) == {"status": "ok"}
    assert galileo.runtime.store.keepouts("floor1") == []
    assert galileo.delete("/navigation/virtual_wall", map_name="floor1",
                          path_name="nopath").status_code == 404
