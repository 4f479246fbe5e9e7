"""Floors and maps over the wire: /get_maps, /publish_map, /clear_map, /save_map,
/save_ext_map, /delete_map, /delete_allmap, and /map and /wall_update around them."""

from __future__ import annotations

import base64
import io
import json

import numpy as np
from PIL import Image

from polynav.protocols.rosbridge.androidmsg import ids
from tests.protocols.rosbridge.androidmsg.conftest import Robot

COVERED = {
    "/get_maps": "test_get_maps_lists_floors_maps_and_points",
    "/publish_map": "test_publish_map_loads_or_only_sets_the_default",
    "/clear_map": "test_clear_map_then_save_map_makes_a_new_floor",
    "/save_map": "test_clear_map_then_save_map_makes_a_new_floor",
    "/save_ext_map": "test_save_ext_map_takes_an_erased_picture",
    "/wall_update": "test_save_ext_map_takes_an_erased_picture",
    "/delete_map": "test_delete_map_and_its_empty_floor",
    "/delete_allmap": "test_delete_allmap_takes_zero_ids",
}


def _maps(robot: Robot) -> dict[str, object]:
    values = robot.call("/get_maps")
    assert values["success"] is True
    body: dict[str, object] = json.loads(values["message"])
    return body


def test_get_maps_lists_floors_maps_and_points(robot: Robot) -> None:
    body = _maps(robot)
    assert list(body) == ["defaultFloor", "floors"] and body["defaultFloor"] == 1
    floors = body["floors"]
    assert isinstance(floors, list)
    assert [f["floorId"] for f in floors] == [1, 2, 3]
    first = floors[0]
    assert first["floorName"] == "floor1" and first["defaultmap"] == ids.map_id("floor1")
    (floor1,) = first["maps"]
    assert list(floor1) == ["mapid", "initialid", "chargeid", "mapName", "systemPoints",
                            "shapeAreas", "mapFile", "points"]
    assert floor1["mapName"] == "floor1"
    assert floor1["initialid"] == robot.store.point("floor1", "initial").number
    assert {p["type"] for p in floor1["systemPoints"]} == {"initial", "charge"}
    lobby = next(p for p in floor1["points"] if p["pointName"] == "lobby")
    assert lobby == {"pointid": 3, "pointName": "lobby", "positionx": 5.5, "positiony": 12.5,
                     "positionyaw": 0.0}


def test_publish_map_loads_or_only_sets_the_default(robot: Robot) -> None:
    robot.subscribe("/androidmsg_mapstatus")
    floor2 = {"floor_id": 2, "map_id": ids.map_id("floor2")}
    assert robot.call("/publish_map", {"type": 1, **floor2}) == {}
    assert robot.runtime.status().mode == "free"
    assert robot.call("/publish_map", {"type": 0, "floor_id": 1,
                                       "map_id": ids.map_id("floor1")}) == {}
    assert robot.runtime.map_name == "floor1"
    assert robot.codes("/androidmsg_mapstatus", lambda c: 60 in c, 5) == [60]
    assert "no map 5 on floor 1" in robot.fail("/publish_map", {"type": 0, "floor_id": 1,
                                                                "map_id": 5})
    assert "no floor 9" in robot.fail("/publish_map", {"type": 0, "floor_id": 9, "map_id": 1})
    assert "'type'" in robot.fail("/publish_map", {"type": 3, **floor2})


def test_clear_map_then_save_map_makes_a_new_floor(robot: Robot) -> None:
    assert robot.call("/clear_map") == {"result": 0}
    assert robot.runtime.status().mode == "mapping"
    robot.runtime.advance(3.0)
    assert "exists" in robot.fail("/save_map", {"type": 2, "floor_id": 0,
                                                "floor_name": "floor1", "map_name": "x"})
    values = robot.call("/save_map", {"type": 2, "floor_id": 0, "floor_name": "annex",
                                      "map_name": "annex-map"})
    assert values["status"] == 0
    floors = {f["floorName"]: f for f in _maps(robot)["floors"]}  # type: ignore[union-attr]
    assert floors["annex"]["floorId"] == 4
    assert [m["mapName"] for m in floors["annex"]["maps"]] == ["annex-map"]
    assert "not mapping" in robot.fail("/save_map", {"type": 0, "floor_id": 0,
                                                     "floor_name": "", "map_name": "y"})


def _picture(robot: Robot, name: str) -> str:
    grid = robot.store.load_map(name)
    grey = np.full(grid.data.shape, 205, dtype=np.uint8)
    grey[grid.data == 0] = 254
    grey[grid.data == 100] = 0
    grey[:10, :10] = 254  # "erase" the bottom-left corner: free
    out = io.BytesIO()
    Image.fromarray(np.flipud(grey)).save(out, format="PNG")
    return base64.b64encode(out.getvalue()).decode()


def test_save_ext_map_takes_an_erased_picture(robot: Robot) -> None:
    robot.subscribe("/wall_update")
    picture = _picture(robot, "floor1")
    values = robot.call("/save_ext_map", {"type": 1, "floor_id": 1, "floor_name": "",
                                          "map_name": "floor1-erased", "base64": picture})
    assert values["status"] == 0
    saved = robot.store.load_map("floor1-erased")
    original = robot.store.load_map("floor1")
    assert (saved.data[:10, :10] == 0).all()
    assert np.array_equal(saved.data[10:, 10:], original.data[10:, 10:])
    assert robot.store.map_record("floor1-erased").floor == "floor1"
    assert robot.codes("/wall_update", lambda c: bool(c), 1) == [1]
    assert "not base64" in robot.fail("/save_ext_map", {"type": 1, "floor_id": 1,
                                                        "map_name": "z", "base64": "@@@"})
    small = io.BytesIO()
    Image.new("L", (4, 4), 254).save(small, format="PNG")
    assert "4 x 4" in robot.fail("/save_ext_map", {
        "type": 1, "floor_id": 1, "map_name": "z",
        "base64": base64.b64encode(small.getvalue()).decode()})


def test_delete_map_and_its_empty_floor(robot: Robot) -> None:
    robot.runtime.start_navigation("floor1", point="initial")
    assert "in use" in robot.fail("/delete_map", {"floor_id": 1,
                                                  "map_id": ids.map_id("floor1")})
    assert robot.call("/delete_map", {"floor_id": 3, "map_id": ids.map_id("floor3")}) == {}
    floors = [f["floorName"] for f in _maps(robot)["floors"]]  # type: ignore[union-attr]
    assert floors == ["floor1", "floor2"]


def test_delete_allmap_takes_zero_ids(robot: Robot) -> None:
    assert "floor_id 0" in robot.fail("/delete_allmap", {"floor_id": 1, "map_id": 0})
    assert robot.call("/delete_allmap", {"floor_id": 0, "map_id": 0}) == {}
    assert _maps(robot)["floors"] == []
