"""The robots of other processes, heard over the broker and put into this process's scene.

When a site's robots are simulated in several processes (each a
:class:`~polynav.house.building.Building` with its share of the robots, on one broker), each
process must still see the others' robots: :class:`RemoteRobots` listens to every vehicle's
``visualization`` (validated against its VDA 5050 schema) and ``connection`` on the broker,
leaves out the robots simulated here, and hands the rest to the scene as
:class:`~polynav.robot.sim.remote_bodies.RemoteBodies`, where lidars see them, people stop for
them and a local robot moving into one is stopped and counted.

A sample's time is its header's timestamp on the site's calendar (``epoch`` + site time: the
processes share one epoch and run their clocks at one pace), so the scene moves it on for the
time since it was taken. A robot whose connection says OFFLINE or CONNECTIONBROKEN is taken out.
:meth:`RemoteRobots.pull` runs on the building's loop (:meth:`attach` makes it a step listener
of one of the building's runtimes), every ``pull_period`` of site time; with ``max_lead`` it
also keeps this process from running ahead of the others.
"""

from __future__ import annotations

import datetime as dt
import logging
import time
from collections.abc import Callable, Iterable

import orjson

from polynav.fleet import messages as m
from polynav.fleet.mqtt_transport import MqttTransport
from polynav.robot.sim.remote_bodies import RemoteBodies, RemoteSample
from polynav.robot.sim.scene import Scene
from polynav.runtime.robot_runtime import RobotRuntime

log = logging.getLogger(__name__)


class RemoteRobots:
    """Feeds ``scene`` the robots simulated elsewhere (see the module docstring).

    Args:
        scene: this process's scene (its ``remote`` is set here).
        mqtt: a connection to the site's broker.
        local: the serial numbers simulated in this process.
        floors: the floor of each map (``mapId`` -> floor name).
        epoch: the UTC moment site time 0 stands for, shared by the processes.
        radius: the remote robots' discs [m].
        version: the VDA 5050 version spoken (messages are checked against its schemas).
        manufacturer: the third level of the topics.
        pull_period: how often the messages are read [s of site time].
        max_extrapolation: how long a sample is moved on along its velocity [s].
        max_lead: how far [s of site time] this process may run ahead of the slowest other
            one (by its robots' latest samples): past it, the pull waits on the loop, up to
            ``max_hold`` [s of wall time] each time, for the others to catch up. Processes
            that cannot keep their pace then slow down together instead of drifting apart;
            None: never wait.
        max_hold: the longest one pull waits [s of wall time].
    """

    def __init__(self, scene: Scene, mqtt: MqttTransport, *, local: Iterable[str],
                 floors: dict[str, str], epoch: dt.datetime, radius: float,
                 version: str = m.DEFAULT_VERSION, manufacturer: str = m.DEFAULT_MANUFACTURER,
                 pull_period: float = 0.05, max_extrapolation: float = 1.0,
                 max_lead: float | None = None, max_hold: float = 0.2) -> None:
        self.bodies = RemoteBodies(max_extrapolation=max_extrapolation)
        scene.remote = self.bodies
        self._local = frozenset(local)
        self._floors = floors
        self._epoch = epoch
        self._radius = radius
        self._pull_period = pull_period
        self._next = 0.0
        self._visualization = mqtt.subscribe_raw(
            m.topic("+", m.Visualization, manufacturer), version=version)
        self._connection = mqtt.subscribe_raw(
            m.topic("+", m.Connection, manufacturer), version=version)
        self.samples = 0
        self.unusable = 0
        self._max_lead = max_lead
        self._max_hold = max_hold
        self.held = 0.0
        """Wall seconds spent waiting for slower processes."""

    def attach(self, runtime: RobotRuntime) -> Callable[[], None]:
        """Pull on ``runtime``'s loop after its physics steps; returns the detach function."""
        return runtime.add_step_listener(self._stepped)

    def _stepped(self, now: float) -> None:
        if now + 1e-9 < self._next:
            return
        self._next = now + self._pull_period
        self.pull(now)
        if self._max_lead is None:
            return
        started = time.monotonic()
        while True:
            slowest = self.bodies.slowest_clock()
            waited = time.monotonic() - started
            if slowest is None or now - slowest <= self._max_lead or waited >= self._max_hold:
                self.held += waited
                return
            time.sleep(0.005)
            self.pull(now)

    def pull(self, now: float) -> None:
        """Take what arrived: poses into the scene, robots gone offline out of it."""
        for message in self._connection.drain():
            serial = message.topic.split("/")[3]
            state = orjson.loads(message.payload).get("connectionState")
            if serial not in self._local and state in ("OFFLINE", "CONNECTIONBROKEN"):
                self.bodies.forget(serial)
        for message in self._visualization.drain():
            serial = message.topic.split("/")[3]
            if serial in self._local:
                continue
            sample = self._sample(serial, orjson.loads(message.payload))
            if sample is None:
                self.unusable += 1
                continue
            self.samples += 1
            self.bodies.update(sample, received=now)

    def _sample(self, serial: str, raw: dict[str, object]) -> RemoteSample | None:
        position = raw.get("agvPosition")
        if not isinstance(position, dict):
            return None
        floor = self._floors.get(str(position.get("mapId")))
        stamp = raw.get("timestamp")
        if floor is None or not isinstance(stamp, str):
            return None
        try:
            moment = dt.datetime.fromisoformat(stamp.replace("Z", "+00:00"))
        except ValueError:
            return None
        velocity = raw.get("velocity")
        linear = omega = 0.0
        if isinstance(velocity, dict):
            linear = float(velocity.get("vx", 0.0))
            omega = float(velocity.get("omega", 0.0))
        return RemoteSample(serial, floor, float(position["x"]), float(position["y"]),
                            float(position["theta"]), linear, omega,
                            (moment - self._epoch).total_seconds(), self._radius)
