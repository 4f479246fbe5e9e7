"""The robot's streams on the ROS graph: rates on simulated time, fields, frames and stamps,
messages between physics steps carried to their own stamps, ``/map`` (orientation, a re-saved
map, the growing map while mapping); ``/cmd_vel`` drives the simulated robot and stops with
the dead-man; every stream over the wire; and the listener's cost per step.
"""

from __future__ import annotations

import contextlib
import math
import statistics
import time
from collections import defaultdict
from collections.abc import Callable, Iterator
from typing import Any

import numpy as np
import pytest

from polynav.maps.map import Map
from polynav.protocols.ros_graph import Graph, RosError
from polynav.protocols.rosbridge.robot_topics import RATES, TF_STATIC, add_robot_topics
from polynav.rosmsg import decode
from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds.world import World
from tests.protocols.rosbridge.conftest import Client, rosbridge

COVERED = {
    "/map": "test_every_stream_over_the_wire",
    "/tracked_pose": "test_every_stream_over_the_wire",
    "/imu/data": "test_every_stream_over_the_wire",
    "/raw_odom": "test_every_stream_over_the_wire",
    "/scan": "test_every_stream_over_the_wire",
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


def _settle(runtime: RobotRuntime, done: Callable[[], bool], wall: float = 15.0) -> bool:
    """Advance the runtime in small steps until ``done()`` (the map thread answers on its own
    thread, so wait on the wall clock too)."""
    deadline = time.monotonic() + wall
    while not done():
        if time.monotonic() > deadline:
            return False
        runtime.advance(0.1)
        time.sleep(0.01)
    return True


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
    assert _settle(runtime, lambda: graph.latched("/map") is not None)
    msg = graph.latched("/map")
    assert msg is not None and msg["header"]["frame_id"] == "map"
    grid = world.floor(world.start_floor).map
    info = msg["info"]
    assert (info["width"], info["height"]) == (grid.info.width, grid.info.height)
    assert np.array_equal(np.asarray(msg["data"]).reshape(info["height"], info["width"]),
                          grid.data)
    # Read cells as a ROS client does (row 0 at the origin, the bottom; index col + row *
    # width) at the world points of walls and of free floor.
    origin = info["origin"]["position"]

    def ros_cell(x: float, y: float) -> int:
        col = math.floor((x - origin["x"]) / info["resolution"])
        row = math.floor((y - origin["y"]) / info["resolution"])
        return int(msg["data"][col + row * info["width"]])

    for value in (100, 0):
        cells = np.argwhere(grid.data == value)
        assert len(cells)
        for iy, ix in cells[:: max(1, len(cells) // 100)]:
            assert ros_cell(*grid.info.cell_to_world(ix, iy)) == value
    assert not np.array_equal(grid.data, np.flipud(grid.data))  # a flip would show


def test_a_map_saved_again_is_sent_again(runtime: RobotRuntime, store: SiteStore,
                                         streamed: tuple[Graph, Recorder]) -> None:
    graph, rec = streamed
    assert _settle(runtime, lambda: graph.latched("/map") is not None)
    name = store.floor(runtime.status().floor or "").map_name
    grid = store.load_map(name)
    data = grid.data.copy()
    data[:5, :7] = 100  # a wall in the bottom-left corner
    store.save_map(name, Map(grid.info, data))
    assert _settle(runtime, lambda: len(rec.messages["/map"]) >= 2)
    msg = rec.messages["/map"][-1]
    info = msg["info"]
    cells = np.asarray(msg["data"]).reshape(info["height"], info["width"])
    assert np.array_equal(cells, data)
    # The new wall is at the origin (bottom-left) in ROS's cell order, not at the top.
    res, origin = info["resolution"], info["origin"]["position"]
    assert msg["data"][0] == 100 and msg["data"][6 + 4 * info["width"]] == 100
    top_left = (info["height"] - 1) * info["width"]
    assert msg["data"][top_left] == grid.data[-1, 0]
    assert not Map(grid.info, data).is_free_at(origin["x"] + 0.5 * res, origin["y"] + 0.5 * res)
    assert msg["header"]["seq"] == rec.messages["/map"][0]["header"]["seq"] + 1
    runtime.advance(3.0)  # nothing changed since: nothing sent
    time.sleep(0.2)
    assert len(rec.messages["/map"]) == 2


def test_while_mapping_the_growing_map_is_sent(runtime: RobotRuntime,
                                               streamed: tuple[Graph, Recorder]) -> None:
    graph, rec = streamed
    graph.retain("/map")
    assert _settle(runtime, lambda: graph.latched("/map") is not None)
    site = graph.latched("/map")
    assert site is not None
    runtime.start_mapping()
    assert _settle(runtime, lambda: graph.latched("/map") is not site)
    first = graph.latched("/map")
    assert first is not None and first["info"]["width"] < site["info"]["width"]
    for _ in range(30):  # drive and turn: the map grows with what the robot sees
        runtime.teleop(0.3, 0.3)
        runtime.advance(0.2)
    assert _settle(runtime, lambda: len(rec.messages["/map"]) >= 3)
    last = rec.messages["/map"][-1]

    def known(msg: dict[str, Any]) -> int:
        return int(np.count_nonzero(np.asarray(msg["data"]) != -1))

    assert known(last) > known(first)
    stamps = [_stamp(m) for m in rec.messages["/map"]]
    assert stamps == sorted(stamps)
    # At the low rate: one every 2 s of the runtime's clock at most.
    assert all(b - a >= 2.0 - 1e-6 for a, b in zip(stamps[1:], stamps[2:], strict=False))


def test_messages_between_physics_steps_carry_the_reading_to_their_stamp(
        runtime: RobotRuntime, streamed: tuple[Graph, Recorder]) -> None:
    _, rec = streamed
    for _ in range(10):
        runtime.teleop(0.3, 0.6)
        runtime.advance(0.1)
    rec.messages.clear()
    runtime.teleop(0.3, 0.6)
    runtime.advance(0.2)
    odometry = runtime.robot.read_odometry()
    imu = rec.messages["/imu/data"]
    yaws = np.unwrap([decode.yaw(m["orientation"]) for m in imu])
    rate = np.mean([m["angular_velocity"]["z"] for m in imu])
    assert rate > 0.3
    # 150 Hz over 50 Hz steps: three messages a step, each turned by its own 1/150 s.
    assert np.allclose(np.diff(yaws), rate / 150.0, rtol=0.2), np.diff(yaws)
    poses = [decode.pose(m["pose"]["pose"]) for m in rec.messages["/raw_odom"]]
    steps = [a.distance_to(b) for a, b in zip(poses, poses[1:], strict=False)]
    speed = odometry.twist.linear
    assert speed > 0.2
    assert np.allclose(steps, speed / 100.0, rtol=0.2), steps
    # The message stamped at the step is the step's reading itself.
    last = rec.messages["/raw_odom"][-1]
    assert _stamp(last) == pytest.approx(odometry.stamp, abs=1e-6)
    assert decode.pose(last["pose"]["pose"]).distance_to(odometry.pose) < 1e-6
    tracked = rec.messages["/tracked_pose"]
    moved = [decode.pose(a["pose"]).distance_to(decode.pose(b["pose"]))
             for a, b in zip(tracked, tracked[1:], strict=False)]
    assert np.allclose(moved, speed / 15.0, rtol=0.3), moved


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


def test_the_step_listener_is_quick(runtime: RobotRuntime,
                                    monkeypatch: pytest.MonkeyPatch) -> None:
    """Every stream subscribed: the listener's own time per physics step (the median, which
    load on a shared machine hardly moves; about 0.2 ms here) stays far below the 20 ms step."""
    costs: list[float] = []
    add = runtime.add_step_listener

    def timed(listener: Callable[[float], None]) -> Callable[[], None]:
        def run(now: float) -> None:
            start = time.perf_counter()
            listener(now)
            costs.append(time.perf_counter() - start)

        return add(run)

    monkeypatch.setattr(runtime, "add_step_listener", timed)
    graph = Graph()
    stop = add_robot_topics(graph, runtime)
    for name in STREAMS:
        graph.retain(name)
    graph.add_sink(lambda name, msg: None)
    runtime.advance(4.0)
    stop()
    assert len(costs) == 200
    assert statistics.median(costs) < 0.002, statistics.median(costs)


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


def test_every_stream_over_the_wire(runtime: RobotRuntime) -> None:
    """Each topic subscribed by a raw rosbridge client: its messages arrive with the type's
    fields, frames and increasing stamps; latched /map and /tf_static at once."""
    graph = Graph()
    stop = add_robot_topics(graph, runtime)
    types = {t.name: t.type for t in graph.topics()}
    with rosbridge(graph, runtime.clock) as server:
        client = Client(server.port)
        try:
            assert _settle(runtime, lambda: graph.latched("/map") is not None)
            for name in (*STREAMS, "/map", TF_STATIC.name):
                client.send({"op": "subscribe", "topic": name, "type": types[name],
                             "queue_length": 1000})
            got: dict[str, list[dict[str, Any]]] = defaultdict(list)
            client.send({"op": "call_service", "id": "sync", "service": "/rosapi/get_time"})
            while (frame := client.recv())["op"] != "service_response":  # subscriptions in
                got[frame["topic"]].append(frame["msg"])  # the latched ones come at once
            runtime.advance(1.0)
            deadline = time.monotonic() + 15.0
            # Enough of each to check (the rates are checked on the graph: here a burst of a
            # simulated second may meet the server's bounded queue of 100 on a loaded machine).
            wanted = {"/tracked_pose": 10, "/imu/data": 50, "/raw_odom": 50, "/scan": 10,
                      "/odom": 30, "/imu": 30, "/tf": 30, "/battery_state": 1, "/clock": 30,
                      "/map": 1, "/tf_static": 1}
            while any(len(got[n]) < k for n, k in wanted.items()):
                try:
                    frame = client.recv_op("publish",
                                           timeout=max(0.1, deadline - time.monotonic()))
                except TimeoutError:
                    pytest.fail(f"messages by topic: { {n: len(got[n]) for n in wanted} }")
                got[frame["topic"]].append(frame["msg"])
            # Read what is left (the clock stands still now): a client that stops reading
            # holds up the close handshake behind the frames it has not taken.
            with contextlib.suppress(TimeoutError):
                while True:
                    client.recv(timeout=0.3)
        finally:
            client.close()
    stop()
    frames = {"/tracked_pose": "map", "/imu/data": "imu_link", "/raw_odom": "odom",
              "/scan": "laser", "/odom": "odom", "/imu": "imu_link", "/map": "map",
              "/battery_state": "base_link"}
    for name, frame_id in frames.items():
        assert got[name][0]["header"]["frame_id"] == frame_id, name
        stamps = [_stamp(m) for m in got[name]]
        assert stamps == sorted(stamps), name
    assert set(got["/raw_odom"][0]["pose"]) == {"pose", "covariance"}
    assert set(got["/imu/data"][0]) >= {"orientation", "angular_velocity",
                                        "linear_acceleration", "orientation_covariance"}
    assert got["/scan"][0]["ranges"] and got["/scan"][0]["range_max"] > 0
    assert got["/map"][0]["info"]["width"] * got["/map"][0]["info"]["height"] == len(
        got["/map"][0]["data"])
    assert got["/tf"][0]["transforms"][0]["child_frame_id"] == "base_link"
    assert got["/tf_static"][0]["transforms"][0]["child_frame_id"] == "laser"
    assert 0.0 < got["/battery_state"][0]["percentage"] <= 1.0
    clocks = [c["clock"]["secs"] + c["clock"]["nsecs"] * 1e-9 for c in got["/clock"]]
    assert clocks == sorted(clocks) and len(set(clocks)) == len(clocks)
