"""Virtual walls, special regions and points over the wire: /set_shape, /set_region,
/point_set, /delete_test_point, and /androidmsg_virtualmapstatus."""

from __future__ import annotations

import json

from polynav.maps.keepout import CircleZone, ForbiddenZone, GuidedZone, VirtualWall
from polynav.site import PointKind
from tests.protocols.rosbridge.androidmsg.conftest import Robot

COVERED = {
    "/set_shape": "test_set_shape_adds_and_deletes_walls_on_the_running_costmap",
    "/androidmsg_virtualmapstatus": "test_set_shape_adds_and_deletes_walls_on_the_running_costmap",
    "/set_region": "test_set_region_makes_the_robot_cross_along_its_route",
    "/point_set": "test_point_set_records_the_robots_pose",
    "/delete_test_point": "test_delete_test_point_keeps_system_points",
}



def _p(x: float, y: float) -> dict[str, float]:
    return {"x": x, "y": y, "z": 0.0}


def test_set_shape_adds_and_deletes_walls_on_the_running_costmap(robot: Robot) -> None:
    robot.start_navigation()
    robot.subscribe("/androidmsg_virtualmapstatus")
    wall = {"type": "lines", "points": [_p(6.0, 10.0), _p(7.0, 10.0)], "closed": False}
    assert robot.call("/set_shape", wall) == {"success": True}
    assert robot.call("/set_shape", {"type": "circle", "points": [_p(10.0, 9.0)],
                                     "radius": 0.4}) == {"success": True}
    assert robot.call("/set_shape", {"type": "lines", "closed": True, "points": [
        _p(1, 1), _p(2, 1), _p(2, 2)]}) == {"success": True}
    kept = robot.store.keepouts("floor1")
    assert [type(k) for k in kept] == [VirtualWall, CircleZone, ForbiddenZone]
    stack = robot.runtime.navigation_stack
    assert stack is not None
    cost = stack.costmap.cost_at(10.0, 9.0)  # the circle is on the running costmap now
    assert cost >= 253, cost
    shapes = json.loads(robot.call("/get_maps")["message"])["floors"][0]["maps"][0]["shapeAreas"]
    circle = next(s for s in shapes if s["type"] == "circle")
    assert circle["radius"] == 0.4 and circle["points"] == [_p(10.0, 9.0)]
    assert robot.call("/set_shape", {"type": "circle", "shapeId": circle["shapeId"],
                                     "points": [], "radius": 0}) == {"success": True}
    assert [type(k) for k in robot.store.keepouts("floor1")] == [VirtualWall, ForbiddenZone]
    assert "no virtual wall" in robot.fail("/set_shape", {"type": "lines", "shapeId": 12345,
                                                          "points": []})
    assert "'radius'" in robot.fail("/set_shape", {"type": "circle", "points": [_p(1, 1)]})
    assert "'type'" in robot.fail("/set_shape", {"type": "blob", "points": []})
    codes = robot.codes("/androidmsg_virtualmapstatus", lambda c: len(c) >= 7, 1)
    assert codes[:5] == [62, 62, 62, 62, 63]


def test_set_region_makes_the_robot_cross_along_its_route(robot: Robot) -> None:
    robot.start_navigation()
    # A band across the lobby's approach, crossed only along a lane at x = 9.4 (radius 0.6).
    region = {"type": "lines", "closed": True, "radius": 0.6,
              "points": [_p(2.0, 10.0), _p(10.0, 10.0), _p(10.0, 11.0), _p(2.0, 11.0)],
              "points2": [_p(9.4, 9.6), _p(9.4, 11.4)],
              "startPointWaits": [_p(9.4, 9.2)], "endPointWaits": [_p(9.4, 11.8)]}
    assert robot.call("/set_region", region) == {"success": True}
    (zone,) = [k for k in robot.store.keepouts("floor1") if isinstance(k, GuidedZone)]
    assert zone.route == ((9.4, 9.6), (9.4, 11.4)) and zone.lane_width == 1.2
    assert zone.start_waits == ((9.4, 9.2),)
    listed = json.loads(robot.call("/get_maps")["message"])["floors"][0]["maps"][0]
    (shape,) = [s for s in listed["shapeAreas"] if s.get("region")]
    assert shape["points2"] == region["points2"]
    robot.runtime.go_to(point="lobby")
    crossed: list[float] = []
    while robot.runtime.status().navigation_state == "running":
        robot.runtime.advance(0.2)
        pose = robot.runtime.simulation.true_pose
        if 10.0 < pose.y < 11.0:
            crossed.append(pose.x)
        assert robot.runtime.now() < 200
    assert robot.runtime.status().navigation_state == "succeeded"
    assert crossed and all(8.7 < x < 10.0 for x in crossed), crossed
    assert robot.call("/set_region", {"type": "lines", "shapeId": shape["shapeId"]}) == {
        "success": True}
    assert not [k for k in robot.store.keepouts("floor1") if isinstance(k, GuidedZone)]
    assert "closed" in robot.fail("/set_region", {**region, "closed": False})
    assert "at least 3" in robot.fail("/set_region", {**region, "points": [_p(1, 1)]})
    assert "at least 2" in robot.fail("/set_region", {**region, "points2": []})
    assert "no special region" in robot.fail("/set_region", {"type": "lines", "shapeId": 7})


def test_point_set_records_the_robots_pose(robot: Robot) -> None:
    assert robot.call("/point_set", {"point_mode": 0, "point_name": "here",
                                     "point_id": 0}) == {"result": 1}  # no map yet
    robot.start_navigation()
    assert robot.call("/point_set", {"point_mode": 0, "point_name": "here",
                                     "point_id": 0}) == {"result": 0}
    point = robot.store.point("floor1", "here")
    assert point.pose.distance_to(robot.runtime.status().pose) < 1e-6
    assert robot.call("/point_set", {"point_mode": 3, "point_name": "lift door",
                                     "point_id": 0}) == {"result": 0}
    assert robot.store.point("floor1", "lift door").kind is PointKind.LIFT_OUTSIDE
    assert robot.call("/point_set", {"point_mode": 0, "point_name": " ",
                                     "point_id": 0}) == {"result": 3}
    assert robot.call("/point_set", {"point_mode": 0, "point_name": "here",
                                     "point_id": 0}) == {"result": 4}
    lift = robot.ids_of("floor1", "lift door")["point_id"]
    assert robot.call("/point_set", {"point_mode": 3, "point_name": "",
                                     "point_id": lift}) == {"result": 0}
    assert "lift door" not in {p.name for p in robot.store.points(map_name="floor1")}
    assert "'point_mode'" in robot.fail("/point_set", {"point_mode": 9, "point_name": "x"})


def test_delete_test_point_keeps_system_points(robot: Robot) -> None:
    lobby = robot.ids_of("floor1", "lobby")
    assert robot.call("/delete_test_point", lobby) == {"result": 0}
    assert "lobby" not in {p.name for p in robot.store.points(map_name="floor1")}
    assert "cannot be deleted" in robot.fail("/delete_test_point",
                                             robot.ids_of("floor1", "charger"))
    assert "no point" in robot.fail("/delete_test_point", lobby)
