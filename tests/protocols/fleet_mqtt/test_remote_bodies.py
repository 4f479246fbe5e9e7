"""A robot simulated in another process, heard over a real Mosquitto, is a body in this scene:
the lidar sees it, a move into it is a collision with a ``"robot"`` naming it, it moves on along
its velocity between samples, and it leaves the scene when its connection says OFFLINE."""

from __future__ import annotations

import datetime as dt
import math
import time

import numpy as np
import pytest

from polynav.fleet import codec
from polynav.fleet import messages as m
from polynav.fleet.mqtt_transport import MqttTransport
from polynav.geometry import Pose2D, Twist
from polynav.house.remote_robots import RemoteRobots
from polynav.robot.sim.scene import RobotContact
from polynav.robot.sim.simulation import Simulation
from polynav.worlds import load_world
from polynav.worlds.world import WorldFloor
from tests.protocols.fleet_mqtt.conftest import WAIT, TransportFactory

RADIUS = 0.3


def _forward_range(sim: Simulation) -> float:
    scan = sim.scan
    assert scan is not None
    ahead = np.abs(scan.angles) < math.radians(3.0)
    return float(np.min(scan.ranges[ahead]))


def _listening(connect: TransportFactory
               ) -> tuple[Simulation, WorldFloor, RemoteRobots, MqttTransport, m.Headers]:
    """robot1 simulated on the demo's first floor, hearing the other robots over the broker;
    the transport of a robot9 to publish as, and headers to stamp its messages with."""
    world = load_world("demo")
    floor = world.floors[0]
    sim = Simulation(world, floor=floor.name, people=False, name="robot1")
    epoch = dt.datetime.now(dt.UTC)
    client = connect("test/remote")
    remote = RemoteRobots(sim.scene, client, local={"robot1"},
                          floors={floor.map_name: floor.name}, epoch=epoch, radius=RADIUS)
    assert client.wait_subscribed(WAIT)
    headers = m.Headers(m.DEFAULT_VERSION, m.DEFAULT_MANUFACTURER, sim.scene.clock.now, epoch)
    return sim, floor, remote, connect("test/robot9"), headers


def test_a_remote_robot_is_seen_collided_with_and_forgotten(connect: TransportFactory) -> None:
    sim, floor, remote, other, headers = _listening(connect)
    sim.step(0.5)
    clear = _forward_range(sim)
    assert clear > 1.5, "the test needs room ahead of the start pose"
    pose = sim.true_pose
    gap = min(2.0, clear - 0.5)

    def publish(x: float, y: float, linear: float) -> None:
        other.publish(m.topic("robot9", m.Visualization), m.Visualization(
            headers.stamp("robot9", m.Visualization),
            m.AgvPosition(x, y, pose.theta, floor.map_name, True, 1.0),
            m.Velocity(linear, 0.0, 0.0)))

    def heard(count: int) -> None:
        deadline = time.monotonic() + WAIT
        while remote.samples < count:
            assert time.monotonic() < deadline, "the broker did not deliver in time"
            time.sleep(0.01)
            remote.pull(sim.scene.clock.now())

    ahead = Pose2D(pose.x + gap * math.cos(pose.theta), pose.y + gap * math.sin(pose.theta), 0.0)
    publish(ahead.x, ahead.y, 0.0)
    heard(1)
    sim.step(0.5)
    seen = _forward_range(sim)
    assert seen < clear - 0.3
    assert seen == pytest.approx(gap - RADIUS, abs=0.25)  # the lidar sits near the centre

    # Moving on along its velocity: a sample going away at 0.5 m/s is drawn 0.25 m further
    # after 0.5 s, no later sample needed.
    publish(ahead.x, ahead.y, 0.5)
    heard(2)
    sim.step(0.5)
    (x, y, _), = sim.scene.remote.circles(floor.name, sim.scene.clock.now())  # type: ignore[union-attr]
    assert math.hypot(x - ahead.x, y - ahead.y) == pytest.approx(0.25, abs=0.03)
    publish(ahead.x, ahead.y, 0.0)
    heard(3)

    sim.drive(Twist(0.5, 0.0))
    for _ in range(int(2 * gap / 0.5 / sim.physics_period)):
        sim.step()
        if sim.collisions:
            break
    assert [c.obstacle for c in sim.collisions] == ["robot"]
    contact = sim.scene.robot_contacts[-1]
    assert contact == RobotContact(contact.stamp, "robot1", "robot9", True)
    assert sim.true_pose.distance_to(ahead) < 2 * RADIUS + 0.1
    staleness = remote.bodies.staleness()
    assert staleness.samples == 3 and 0.0 <= staleness.worst < 1.0

    other.publish(m.topic("robot9", m.Connection), m.Connection(
        headers.stamp("robot9", m.Connection), m.ConnectionState.OFFLINE))
    deadline = time.monotonic() + WAIT
    while remote.bodies.circles(floor.name, sim.scene.clock.now()).shape[0]:
        assert time.monotonic() < deadline, "OFFLINE did not arrive in time"
        time.sleep(0.01)
        remote.pull(sim.scene.clock.now())
    sim.drive(Twist(0.3, 0.0))
    sim.step(0.5)
    assert len(sim.collisions) == 1  # it has left: the way is free


def test_bad_messages_from_other_robots_are_left_out(connect: TransportFactory) -> None:
    sim, floor, remote, other, headers = _listening(connect)
    topic = m.topic("robot9", m.Visualization)
    other.publish_raw(topic, b"{not json")
    other.publish_raw(topic, b'{"headerId": "one"}')  # breaks the schema
    unknown_map = codec.encode(m.Visualization(
        headers.stamp("robot9", m.Visualization),
        m.AgvPosition(1.0, 1.0, 0.0, "floor9", True, 1.0)))
    other.publish_raw(topic, unknown_map)
    own = codec.encode(m.Visualization(headers.stamp("robot1", m.Visualization),
                                       m.AgvPosition(1.0, 1.0, 0.0, floor.map_name, True, 1.0)))
    other.publish_raw(m.topic("robot1", m.Visualization), own)  # robot1 is simulated here
    deadline = time.monotonic() + WAIT
    while remote.unusable < 1:
        assert time.monotonic() < deadline, "the broker did not deliver in time"
        time.sleep(0.01)
        remote.pull(sim.scene.clock.now())
    time.sleep(0.2)
    remote.pull(sim.scene.clock.now())
    assert remote.samples == 0 and remote.bodies.serials == ()
    sim.step(0.2)  # the scene steps on as before
