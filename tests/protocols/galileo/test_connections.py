"""Target points of every path and connections over real HTTP (galileo-http-b E46–E48)."""

from __future__ import annotations

from typing import Any

from polynav.store.records import ConnectionRecord
from tests.protocols.galileo.conftest import Harness

COVERED = {
    "GET /api/v1/navigation/point_connections": "test_points_and_connections_listing",
    "POST /api/v1/navigation/point_connections": "test_add_and_delete_a_direct_connection",
    "DELETE /api/v1/navigation/point_connections": "test_add_and_delete_a_direct_connection",
}

REQUEST: dict[str, Any] = {"points": [{"map": "floor1", "path": "default", "index": 1},
                                      {"map": "floor2", "path": "default", "index": 1}],
                           "type": "direct"}


def test_points_and_connections_listing(galileo: Harness) -> None:
    body = galileo.ok("GET", "/navigation/point_connections")
    assert set(body) == {"points", "connections"}
    lobby = body["points"][1]
    assert lobby == {"x": 5.5, "y": 12.5, "theta": 0.0, "name": "lobby", "map": "floor1",
                     "path": "default", "index": 1, "type": "floor", "levels": [1]}
    assert {p["map"] for p in body["points"]} == {"floor1", "floor2", "floor3"}
    # A lift of the site shows as an elevator connection between its inside points.
    galileo.runtime.store.set_connections([ConnectionRecord("lift_1", {
        "type": "lift", "car": "lift_1", "stops": [
            {"floor": "floor1", "map": "floor1", "outside": "lift_1_outside",
             "inside": "lift_1_inside"},
            {"floor": "floor2", "map": "floor2", "outside": "lift_1_outside",
             "inside": "lift_1_inside"}]})])
    lifts = galileo.ok("GET", "/navigation/point_connections")["connections"]
    assert len(lifts) == 1 and lifts[0]["type"] == "elevator"
    assert lifts[0]["id"] == "lift_1:floor1-floor2"
    assert [p["index"] for p in lifts[0]["points"]] == [14, 8]
    assert galileo.delete("/navigation/point_connections",
                          id="lift_1:floor1-floor2").status_code == 409


def test_add_and_delete_a_direct_connection(galileo: Harness) -> None:
    galileo.runtime.store.set_connections([])  # the demo's lifts aside: only this one
    body = galileo.ok("POST", "/navigation/point_connections", json=REQUEST)
    assert body["points"] == REQUEST["points"] and body["type"] == "direct"
    assert body["is_available"] is True and len(body["_id"]["$oid"]) == 24
    stored = galileo.runtime.store.connections()
    assert [r.name for r in stored] == [body["id"]]
    data = stored[0].data
    assert (data["type"], data["from"], data["to"]) == (
        "direct", {"map": "floor1", "point": "lobby"}, {"map": "floor2", "point": "lounge"})
    listed = galileo.ok("GET", "/navigation/point_connections")["connections"]
    assert listed[0]["id"] == body["id"]
    assert listed[0]["points"][0] == {"map": "floor1", "path": "default", "index": 1,
                                      "type": "floor", "levels": [1]}
    assert galileo.ok("DELETE", "/navigation/point_connections", params={"id": body["id"]}) == {
        "status": "ok"}
    assert galileo.runtime.store.connections() == []
    assert galileo.delete("/navigation/point_connections", id=body["id"]).status_code == 404


def test_bad_connections_change_nothing(galileo: Harness) -> None:
    before = galileo.runtime.store.connections()
    same_map = {**REQUEST, "points": [REQUEST["points"][0],
                                      {"map": "floor1", "path": "default", "index": 2}]}
    for bad, status in (({**REQUEST, "points": REQUEST["points"][:1]}, 400),
                        (same_map, 400), ({**REQUEST, "type": "elevator"}, 400),
                        ({**REQUEST, "type": "tunnel"}, 400),
                        ({**REQUEST, "is_available": False}, 400),
                        ({**REQUEST, "points": [REQUEST["points"][0],
                                                {"map": "floor2", "path": "default",
                                                 "index": 99}]}, 400),
                        ({**REQUEST, "points": [REQUEST["points"][0],
                                                {"map": "nomap", "path": "default",
                                                 "index": 0}]}, 404),
                        ({"type": "direct"}, 400)):
        response = galileo.post("/navigation/point_connections", bad)
        assert response.status_code == status, (bad, response.text)
    assert galileo.runtime.store.connections() == before
