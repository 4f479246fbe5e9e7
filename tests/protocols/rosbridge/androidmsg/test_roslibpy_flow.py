"""The androidmsg flow driven by roslibpy, a real rosbridge client from PyPI: subscribe to the
navigation status and the tracked pose, read the maps, send a goal by its ids, see "arrived"
(2) and the pose reach the point, on simulated time."""

from __future__ import annotations

import json
import threading
from collections.abc import Iterator
from typing import Any

import pytest

from polynav.protocols.ros_graph import Graph
from polynav.protocols.rosbridge.androidmsg import add_androidmsg
from polynav.protocols.rosbridge.robot_topics import add_robot_topics
from polynav.rosmsg import decode
from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds.world import World
from tests.protocols.rosbridge.conftest import rosbridge

roslibpy = pytest.importorskip("roslibpy")

TIMEOUT = 10.0


@pytest.fixture
def served(world: World, store: SiteStore) -> Iterator[tuple[RobotRuntime, Any]]:
    runtime = RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False))
    graph = Graph()
    detach = [add_robot_topics(graph, runtime), add_androidmsg(graph, runtime)]
    runtime.advance(0.2)
    with rosbridge(graph, runtime.clock) as server:
        ros = roslibpy.Ros(host="127.0.0.1", port=server.port)
        ros.run(timeout=TIMEOUT)
        try:
            yield runtime, ros
        finally:
            ros.close()
    for remove in detach:
        remove()


def test_a_roslibpy_client_sends_a_goal_and_sees_the_robot_arrive(
        served: tuple[RobotRuntime, Any]) -> None:
    runtime, ros = served
    assert "/androidmsg_navigationstatus" in ros.get_topics()  # what clients ask first
    statuses: list[int] = []
    poses: list[dict[str, Any]] = []
    lock = threading.Lock()

    def on_status(msg: dict[str, Any]) -> None:
        with lock:
            statuses.append(msg["data"])

    def on_pose(msg: dict[str, Any]) -> None:
        with lock:
            poses.append(msg)

    status = roslibpy.Topic(ros, "/androidmsg_navigationstatus", "std_msgs/Int16",
                            queue_length=50)
    status.subscribe(on_status)
    tracked = roslibpy.Topic(ros, "/tracked_pose", "geometry_msgs/PoseStamped",
                             queue_length=50)
    tracked.subscribe(on_pose)
    reply = roslibpy.Service(ros, "/get_maps", "std_srvs/Trigger").call(
        roslibpy.ServiceRequest({}), timeout=TIMEOUT)
    body = json.loads(reply["message"])
    floor = body["floors"][0]
    the_map = floor["maps"][0]
    lobby = next(p for p in the_map["points"] if p["pointName"] == "lobby")
    goal = roslibpy.Topic(ros, "/navi_targetgoal", "map_msgs/TargetGoal")
    goal.publish(roslibpy.Message({"floor_id": floor["floorId"], "map_id": the_map["mapid"],
                                   "point_id": lobby["pointid"]}))
    ros.get_time()  # the goal is handled before this answer
    deadline = runtime.now() + 90.0
    while runtime.now() < deadline:
        runtime.advance(0.5)
        ros.get_time()  # lets the messages of this half-second arrive
        with lock:
            if 2 in statuses:
                break
    with lock:
        assert statuses[0] == 1 and 2 in statuses, statuses
        last = decode.pose(poses[-1]["pose"])
    assert abs(last.x - lobby["positionx"]) < 0.1 and abs(last.y - lobby["positiony"]) < 0.1
    status.unsubscribe()
    tracked.unsubscribe()
