"""One polynav drives another's simulated robot over rosbridge, as it would drive a real ROS
base: polynav A simulates the robot and serves its driver topics (``/odom``, ``/scan``,
``/imu``, ``/tf_static``, ``/clock``, ``/cmd_vel``); polynav B runs the whole stack on
:class:`~polynav.robot.rosbridge.RosbridgeBackend` with a map of A's floor. A's rosbridge server
is killed and restarted mid-goal: B holds (its clock is A's and stands still), reconnects and
finishes; A's robot stops meanwhile on its own command timeout.

A runs its loop at 3x; B follows A's ``/clock``, so the outcome does not depend on the
machine's speed (a slower machine only makes it take longer)."""

from __future__ import annotations

import math
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from polynav.geometry import angle_diff
from polynav.protocols.ros_graph import Graph
from polynav.protocols.rosbridge import RosbridgeConfig, RosbridgeThread
from polynav.protocols.rosbridge.robot_topics import add_robot_topics
from polynav.robot.rosbridge import BridgeConfig, RosbridgeBackend
from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds.world import World

pytestmark = pytest.mark.slow

POINTS = ("lobby", "front_desk", "corridor_west", "office_3", "initial")
RESTART_AT = "corridor_west"
GOAL_WALL_TIMEOUT = 120.0


class RobotA:
    """The simulated robot and its rosbridge server (restartable on the same port)."""

    def __init__(self, world: World, data: Path) -> None:
        self.store = SiteStore.open(data, seed_world=world)
        self.runtime = RobotRuntime.simulated(self.store, world,
                                              config=RuntimeConfig(people=False, speed=3.0))
        self.graph = Graph()
        self.detach = add_robot_topics(self.graph, self.runtime)
        self.server: RosbridgeThread | None = RosbridgeThread(
            self.graph, self.runtime.clock, RosbridgeConfig(port=0))
        self.port = self.server.port
        self.runtime.start()

    def kill_server(self) -> None:
        assert self.server is not None
        self.server.stop()
        self.server = None

    def restart_server(self) -> None:
        self.server = RosbridgeThread(self.graph, self.runtime.clock,
                                      RosbridgeConfig(port=self.port))

    def close(self) -> None:
        if self.server is not None:
            self.server.stop()
        self.runtime.stop()
        self.detach()
        self.store.close()


@pytest.fixture
def robot_a(world: World, tmp_path: Path) -> Iterator[RobotA]:
    a = RobotA(world, tmp_path / "a")
    yield a
    a.close()


def _wait(done: object, timeout: float) -> bool:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if done():  # type: ignore[operator]
            return True
        time.sleep(0.05)
    return False


def test_polynav_drives_a_bridged_robot_to_five_points_through_a_server_restart(
        robot_a: RobotA, world: World, store: SiteStore) -> None:
    backend = RosbridgeBackend(BridgeConfig(url=f"ws://127.0.0.1:{robot_a.port}",
                                            silence_timeout=2.0, reconnect_min=0.1,
                                            reconnect_max=0.5))
    try:
        assert backend.wait_ready(10.0) and backend.clock.follows_robot
        b = RobotRuntime.bridged(store, backend, config=RuntimeConfig(people=False))
        b.start()
        try:
            b.start_navigation("floor1", point="initial")
            assert _wait(lambda: b.status().mode == "navigating"
                         and b.status().localization_state == "tracking", 30.0)
            for name in POINTS:
                b.go_to(point=name)
                if name == RESTART_AT:
                    under_way = b.now() + 2.0
                    assert _wait(lambda t=under_way: b.now() > t, 30.0)
                    connects = backend.client.connects
                    robot_a.kill_server()
                    assert _wait(lambda: not backend.connected, 10.0)
                    held = b.now()
                    time.sleep(1.0)
                    assert b.now() == held  # B's clock is A's: it holds
                    assert b.status().navigation_state == "running"
                    robot_a.restart_server()
                    # A new connection, counted once its subscriptions are sent again (the
                    # socket is up a moment before: asserting at once raced it, CI).
                    assert _wait(lambda n=connects: backend.connected
                                 and backend.client.connects > n, 15.0)
                assert _wait(lambda: b.status().navigation_state != "running",
                             GOAL_WALL_TIMEOUT), name
                status = b.status()
                assert status.navigation_state == "succeeded", (name, status.reason)
                truth = robot_a.runtime.simulation.true_pose
                target = store.point("floor1", name).pose
                assert math.hypot(truth.x - target.x, truth.y - target.y) <= 0.1, name
                assert abs(angle_diff(truth.theta, target.theta)) <= 0.1, name
        finally:
            b.stop()
    finally:
        backend.close()
    assert robot_a.runtime.simulation.collisions == []
