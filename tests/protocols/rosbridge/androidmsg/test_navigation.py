"""Goals, stops, charging and moves over the wire: /navi_targetgoal, /navi_stop, /autocharge,
/navi_targetgoalplan, /get_position, /set_navi_cmd."""

from __future__ import annotations

import math

from tests.protocols.rosbridge.androidmsg.conftest import Robot

COVERED = {
    "/navi_targetgoal": "test_navi_targetgoal_drives_to_the_point_and_reports_arrival",
    "/androidmsg_navigationstatus": "test_navi_targetgoal_drives_to_the_point_and_reports_arrival",
    "/navi_stop": "test_navi_stop_stops_and_reports_seven",
    "/autocharge": "test_autocharge_docks_on_the_charger",
    "/navi_targetgoalplan": "test_navi_targetgoalplan_computes_the_distance_or_goes",
    "/get_position": "test_get_position_is_the_robots_pose",
    "/set_navi_cmd": "test_set_navi_cmd_moves_in_cm_and_degrees",
}



def test_navi_targetgoal_drives_to_the_point_and_reports_arrival(robot: Robot) -> None:
    robot.subscribe("/androidmsg_navigationstatus")
    robot.publish("/navi_targetgoal", robot.ids_of("floor1", "lobby"))
    codes = robot.codes("/androidmsg_navigationstatus", lambda c: 2 in c or 3 in c)
    assert codes[0] == 1 and codes[-1] == 2
    target = robot.store.point("floor1", "lobby").pose
    assert robot.runtime.simulation.true_pose.distance_to(target) < 0.1
    # an unknown point: 6, and a status error on the wire
    assert "no point 99999" in robot.status_error({
        "op": "publish", "id": "bad", "topic": "/navi_targetgoal",
        "msg": {**robot.ids_of("floor1", "lobby"), "point_id": 99999}})
    assert robot.graph.latched("/androidmsg_navigationstatus") == {"data": 6}
    assert "'floor_id'" in robot.status_error({
        "op": "publish", "id": "t", "topic": "/navi_targetgoal",
        "msg": {"floor_id": "one", "map_id": 1, "point_id": 1}})


def test_navi_stop_stops_and_reports_seven(robot: Robot) -> None:
    robot.start_navigation()
    robot.subscribe("/androidmsg_navigationstatus")
    robot.publish("/navi_targetgoal", robot.ids_of("floor1", "office_3"))
    robot.codes("/androidmsg_navigationstatus", lambda c: 1 in c)
    robot.runtime.advance(2.0)
    robot.publish("/navi_stop", {"data": 5})
    codes = robot.codes("/androidmsg_navigationstatus", lambda c: 7 in c, timeout=5)
    assert codes[-1] == 7
    assert robot.runtime.status().navigation_state == "canceled"
    assert "must be 5" in robot.status_error({"op": "publish", "id": "s", "topic": "/navi_stop",
                                              "msg": {"data": 4}})


def test_autocharge_docks_on_the_charger(robot: Robot) -> None:
    robot.start_navigation()
    robot.subscribe("/androidmsg_chargestatus")
    robot.publish("/autocharge", {"data": 1})
    codes = robot.codes("/androidmsg_chargestatus", lambda c: 45 in c
                        and robot.runtime.status().charging, timeout=120)
    assert codes[0] == 41 and 45 in codes
    assert "must be 1" in robot.status_error({"op": "publish", "id": "a", "topic": "/autocharge",
                                              "msg": {"data": 2}})


def test_autocharge_without_a_charger_is_code_52(robot: Robot) -> None:
    robot.start_navigation()
    charger = robot.store.point("floor1", "charger")
    robot.store.delete_point("floor1", charger.name)
    robot.subscribe("/androidmsg_navigationstatus")
    assert "no charging pile" in robot.status_error({"op": "publish", "id": "c",
                                                     "topic": "/autocharge", "msg": {"data": 1}})
    assert robot.graph.latched("/androidmsg_navigationstatus") == {"data": 52}


def test_navi_targetgoalplan_computes_the_distance_or_goes(robot: Robot) -> None:
    robot.start_navigation()
    robot.subscribe("/androidmsg_navigationstatus")
    target = robot.ids_of("floor1", "front_desk")
    values = robot.call("/navi_targetgoalplan", {"type": 1, **target})
    here = robot.runtime.status().pose
    goal = robot.store.point("floor1", "front_desk").pose
    assert values["status"] == 0
    assert math.hypot(goal.x - here.x, goal.y - here.y) <= values["distance"] < 20
    assert values["target_point_id"] == target["point_id"]
    assert values["local_floor_id"] == 1 and values["target_floor_id"] == 1
    assert values["localX"] == here.x
    assert robot.codes("/androidmsg_navigationstatus", lambda c: 81 in c, timeout=1)[-1] == 81
    assert robot.runtime.status().navigation_state == "idle"
    robot.call("/navi_targetgoalplan", {"type": 0, **target})
    assert robot.codes("/androidmsg_navigationstatus", lambda c: 2 in c)[-1] == 2
    assert "'type'" in robot.fail("/navi_targetgoalplan", {"type": 7, **target})
    assert "'map_id'" in robot.fail("/navi_targetgoalplan", {"type": 1, "floor_id": 1,
                                                             "point_id": 1})


def test_get_position_is_the_robots_pose(robot: Robot) -> None:
    robot.start_navigation()
    values = robot.call("/get_position")
    pose = robot.runtime.status().pose
    assert values == {"pose": {"x": pose.x, "y": pose.y, "z": 0.0}}


def test_set_navi_cmd_moves_in_cm_and_degrees(robot: Robot) -> None:
    robot.start_navigation()
    start = robot.runtime.simulation.true_pose
    robot.call("/set_navi_cmd", {"cmd": "1", "distance": 50})
    assert robot.wait(lambda: not robot.runtime.local_move_active, 30)
    moved = robot.runtime.simulation.true_pose
    assert abs(start.distance_to(moved) - 0.5) < 0.05
    robot.call("/set_navi_cmd", {"cmd": "3", "distance": 90})
    assert robot.wait(lambda: not robot.runtime.local_move_active, 30)
    turned = robot.runtime.simulation.true_pose.theta - moved.theta
    assert abs(math.remainder(turned - math.pi / 2, 2 * math.pi)) < 0.1
    robot.call("/set_navi_cmd", {"cmd": "4", "distance": 180})
    robot.runtime.advance(0.5)
    robot.call("/set_navi_cmd", {"cmd": "5", "distance": 0})
    assert not robot.runtime.local_move_active
    assert '"1".."5"' in robot.fail("/set_navi_cmd", {"cmd": "9", "distance": 10})
    assert "'distance'" in robot.fail("/set_navi_cmd", {"cmd": "1", "distance": -3})
