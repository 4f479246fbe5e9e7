"""The robot's streams on the ROS graph: rates on simulated time, fields, frames and stamps;
``/cmd_vel`` drives the simulated robot and stops with the dead-man; and the same over the wire.
"""

from __future__ import annotations

import math
from collections import defaultdict
from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest

from polynav.protocols.ros_graph import Graph, RosError
from polynav.protocols.rosbridge.robot_topics import RATES, add_robot_topics
from polynav.rosmsg import decode
from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds.world import World
from tests.protocols.rosbridge.conftest import Client, rosbridge

COVERED = {
    "/map": "test_the_map_is_latched_and_oriented_as_ros",
    "/tracked_pose": "test_streams_over_the_wire",
    "/imu/data": "test_stream_rates_on_simulated_time_are_within_ten_percent",
    "/raw_odom": "test_stream_rates_on_simulated_time_are_within_ten_percent",
    "/scan": "test_streams_over_the_wire",
    "/cmd_vel": "test_streams_over_the_wire",
}

STREAMS = ("/tracked_pose", "/imu/data", "/raw_odom", "/scan", "/odom", "/imu", "/tf",
           "/battery_state", "/clock")


class Recorder:
    def __init__(self, graph: Graph) -> None:
        self.messages: dict[str, list[dict[str, Any]]] = defaultdict(list)
        graph.add_sink(lambda name, msg: self.messages[name].append(msg))


def _stamp(msg: dict[str, Any]) -> float:
    return decode.stamp(msg["header"])


@pytest.fixture
def runtime(world: World, store: SiteStore) -> RobotRuntime:
    return RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False))


@pytest.fixture
def streamed(runtime: RobotRuntime) -> Iterator[tuple[Graph, Recorder]]:
    graph = Graph()
    recorder = Recorder(graph)
    stop = add_robot_topics(graph, runtime)
    for name in STREAMS:
        graph.retain(name)
    yield graph, recorder
    stop()


def test_stream_rates_on_simulated_time_are_within_ten_percent(
        runtime: RobotRuntime, streamed: tuple[Graph, Recorder]) -> None:
    _, rec = streamed
    runtime.advance(1.0)
    rec.messages.clear()
    runtime.advance(4.0)
    expected = {"/tracked_pose": 15.0, "/imu/data": 150.0, "/raw_odom": 100.0, "/scan": 15.0,
                "/odom": 50.0, "/imu": 50.0, "/battery_state": 1.0, "/clock": 50.0}
    for name, rate in expected.items():
        measured = len(rec.messages[name]) / 4.0
        assert abs(measured - rate) <= 0.1 * rate, (name, measured)
    for name in ("/imu/data", "/raw_odom", "/tracked_pose", "/scan"):
        stamps = [_stamp(m) for m in rec.messages[name]]
        assert stamps == sorted(stamps) and len(set(stamps)) == len(stamps), name
        gaps = np.diff(stamps)
        if name != "/scan":
            assert np.allclose(gaps, 1.0 / RATES[name], atol=1e-6), name


def test_stream_fields_frames_and_key_order(runtime: RobotRuntime,
                                            streamed: tuple[Graph, Recorder]) -> None:
    graph, rec = streamed
    runtime.advance(0.5)
    pose = rec.messages["/tracked_pose"][-1]
    assert list(pose) == ["header", "pose"] and pose["header"]["frame_id"] == "map"
    assert list(pose["pose"]["position"]) == ["x", "y", "z"]
    assert list(pose["pose"]["orientation"]) == ["x", "y", "z", "w"]
    assert decode.pose(pose["pose"]).distance_to(runtime.status().pose) < 0.05
    odom = rec.messages["/raw_odom"][-1]
    assert odom["header"]["frame_id"] == "odom" and odom["child_frame_id"] == "base_link"
    assert len(odom["pose"]["covariance"]) == 36
    scan = rec.messages["/scan"][-1]
    assert scan["header"]["frame_id"] == "laser"
    assert len(scan["ranges"]) == round((scan["angle_max"] - scan["angle_min"])
                                        / scan["angle_increment"]) + 1
    assert all(isinstance(r, float) and math.isfinite(r) for r in scan["ranges"])
    imu = rec.messages["/imu/data"][-1]
    assert set(imu) >= {"orientation", "angular_velocity", "linear_acceleration"}
    battery = rec.messages["/battery_state"][-1]
    assert 0.0 < battery["percentage"] <= 1.0
    tf = rec.messages["/tf"][-1]["transforms"]
    assert tf[0]["header"]["frame_id"] == "odom" and tf[0]["child_frame_id"] == "base_link"
    assert len(tf) == 1  # not localized: no map -> odom
    runtime.start_navigation("floor1", point="initial")
    runtime.advance(1.0)
    tf = rec.messages["/tf"][-1]["transforms"]
    assert [t["child_frame_id"] for t in tf] == ["base_link", "odom"]
    odom_in_map = decode.pose({"position": tf[1]["transform"]["translation"],
                               "orientation": tf[1]["transform"]["rotation"]})
    base_in_odom = decode.pose({"position": tf[0]["transform"]["translation"],
                                "orientation": tf[0]["transform"]["rotation"]})
    assert odom_in_map.compose(base_in_odom).distance_to(runtime.status().pose) < 0.05
    static = graph.latched("/tf_static")
    assert static is not None and static["transforms"][0]["child_frame_id"] == "laser"
    clock = rec.messages["/clock"][-1]["clock"]
    assert abs(clock["secs"] + clock["nsecs"] * 1e-9 - runtime.now()) < 0.021


def test_the_map_is_latched_and_oriented_as_ros(runtime: RobotRuntime, world: World,
                                                streamed: tuple[Graph, Recorder]) -> None:
    graph, _ = streamed
    runtime.advance(0.2)
    deadline = 50
    while graph.latched("/map") is None and deadline:
        runtime.advance(0.1)
        deadline -= 1
    msg = graph.latched("/map")
    assert msg is not None
    grid = world.floor(world.start_floor).map
    info = msg["info"]
    assert (info["width"], info["height"]) == (grid.info.width, grid.info.height)
    data = np.asarray(msg["data"]).reshape(info["height"], info["width"])
    # Row 0 is the bottom row (ROS): the cell under a world point is data[iy, ix].
    ix, iy = grid.info.world_to_cell(1.0, 1.0)
    assert data[iy, ix] == grid.data[iy, ix]
    assert np.array_equal(data, grid.data)


def test_cmd_vel_drives_the_robot_and_the_dead_man_stops_it(
        runtime: RobotRuntime, streamed: tuple[Graph, Recorder]) -> None:
    graph, _ = streamed
    runtime.advance(0.5)
    start = runtime.simulation.true_pose
    handle = graph.subscription("/cmd_vel")
    assert handle is not None
    for _ in range(20):
        handle.handle({"linear": {"x": 0.3, "y": 0.0, "z": 0.0},
                       "angular": {"x": 0.0, "y": 0.0, "z": 0.0}})
        runtime.advance(0.1)
    moved = runtime.simulation.true_pose
    assert moved.distance_to(start) > 0.3
    runtime.advance(2.0)  # no more commands: the dead-man stops it
    assert runtime.robot.read_odometry().twist.linear == pytest.approx(0.0, abs=1e-3)
    with pytest.raises(RosError, match="linear"):
        handle.handle({"linear": {"x": "fast"}})
    with pytest.raises(RosError, match="object"):
        handle.handle({"linear": 3})


def test_streams_cost_nothing_while_no_one_subscribes(runtime: RobotRuntime) -> None:
    graph = Graph()
    rec = Recorder(graph)
    stop = add_robot_topics(graph, runtime)
    runtime.advance(1.0)
    assert set(rec.messages) <= {"/map", "/tf_static"}
    stop()


def test_streams_over_the_wire(runtime: RobotRuntime) -> None:
    graph = Graph()
    stop = add_robot_topics(graph, runtime)
    with rosbridge(graph, runtime.clock) as server:
        client = Client(server.port)
        try:
            client.send({"op": "subscribe", "topic": "/tracked_pose",
                         "type": "geometry_msgs/PoseStamped", "queue_length": 100})
            client.send({"op": "subscribe", "topic": "/scan", "queue_length": 100})
            client.call("/rosapi/get_time")
            runtime.advance(1.0)
            poses = [client.recv_op("publish", topic="/tracked_pose") for _ in range(10)]
            assert decode.pose(poses[-1]["msg"]["pose"]).distance_to(
                runtime.status().pose) < 0.1
            scan = client.recv_op("publish", topic="/scan")["msg"]
            assert scan["range_max"] > 0 and scan["ranges"]
            client.send({"op": "publish", "topic": "/cmd_vel",
                         "msg": {"linear": {"x": 0.2}, "angular": {"z": 0.0}}})
            client.call("/rosapi/get_time", ident="sync")
            start = runtime.simulation.true_pose
            deadline = 200
            while runtime.simulation.true_pose.distance_to(start) < 0.01 and deadline:
                runtime.advance(0.02)
                deadline -= 1
            assert runtime.simulation.true_pose.distance_to(start) >= 0.01
        finally:
            client.close()
    stop()
