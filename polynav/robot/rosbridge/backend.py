"""The bridged robot as a runtime backend: its readings, its commands and its clock.

**Time.** A ROS robot in simulation publishes ``/clock`` and its nodes follow it
(``use_sim_time``); a real one does not, and its nodes use the host's clock. The backend does
the same: once odometry comes, it waits ``clock_grace`` for a ``/clock``; if one comes (and
``use_robot_clock``), the runtime's clock is the robot's, else this machine's monotonic clock.
The choice holds for the backend's life. The robot's clock never runs backwards here: when it
restarts (the robot's simulator restarted), the runtime's clock goes on from where it was.
While the connection is away the runtime's clock stands still, either way (a robot clock sends
nothing; this machine's is held), so navigation holds where it was: no timeout runs out and no
progress check fails on readings that cannot come, and it goes on once the robot is back.

Readings are stamped on the runtime's clock: with the robot's clock, the messages' own stamps;
with this machine's clock, the time they arrived.

**Step.** The runtime's loop calls :meth:`RosbridgeBackend.step` once per period; it waits until
the clock has moved a period past the last step, but never more than ``MAX_WAIT`` of wall time,
so the loop keeps running commands while the robot is away.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Sequence
from typing import Any

from polynav.geometry import Pose2D, Twist
from polynav.robot.interface import (
    BatteryState,
    DockSignals,
    ImuReading,
    LaserScan,
    Odometry,
    PersonDetection,
)
from polynav.robot.rosbridge.client import RosbridgeClient
from polynav.robot.rosbridge.config import BridgeConfig
from polynav.rosmsg import decode, encode

log = logging.getLogger(__name__)

#: The longest a step waits for the robot's time to move [wall s].
MAX_WAIT = 0.05


class BridgeClock:
    """The runtime's clock on a bridged robot (see the module docstring)."""

    def __init__(self) -> None:
        self._robot: bool | None = None  # None: not decided yet
        self._offset = 0.0
        self._last_robot = 0.0
        self._now = time.monotonic()
        self._away_since: float | None = None  # wall time the connection dropped
        self._away_total = 0.0  # wall seconds the robot was away, taken out of the clock
        self._changed = threading.Condition()

    @property
    def follows_robot(self) -> bool:
        return bool(self._robot)

    def decide(self, robot_clock: bool) -> None:
        with self._changed:
            if self._robot is None:
                self._robot = robot_clock
                if robot_clock:
                    self._now = self._last_robot  # the runtime's clock reads as the robot's
                log.info("bridged robot: the runtime's clock is %s",
                         "the robot's /clock" if robot_clock else "this machine's")

    def robot_time(self, t: float) -> float:
        """A robot stamp on the runtime's clock (its restarts folded away)."""
        with self._changed:
            if t < self._last_robot - 1.0:  # the robot's clock restarted
                self._offset += self._last_robot - t
                log.warning("bridged robot: its clock went back from %.2f to %.2f s; going on",
                            self._last_robot, t)
            self._last_robot = t
            return t + self._offset

    def tick_robot(self, t: float) -> None:
        """A ``/clock`` message."""
        stamp = self.robot_time(t)
        with self._changed:
            if self._robot:
                self._now = max(self._now, stamp)
                self._changed.notify_all()

    def away(self) -> None:
        """The connection dropped: this machine's clock stands still for the runtime too."""
        with self._changed:
            if self._away_since is None:
                self.now()
                self._away_since = time.monotonic()

    def back(self) -> None:
        """The connection is back: the clock goes on from where it stood."""
        with self._changed:
            if self._away_since is not None:
                self._away_total += time.monotonic() - self._away_since
                self._away_since = None

    def now(self) -> float:
        if not self._robot:
            with self._changed:
                if self._away_since is None:
                    self._now = max(self._now, time.monotonic() - self._away_total)
        return self._now

    def wait_until(self, t: float, timeout: float) -> None:
        """Until the clock passes ``t``, at most ``timeout`` wall seconds."""
        if not self._robot:
            delay = timeout if self._away_since is not None else min(timeout, t - self.now())
            if delay > 0:
                time.sleep(delay)
            return
        with self._changed:
            self._changed.wait_for(lambda: self._now >= t, timeout)


class RosbridgeRobot:
    """The :class:`~polynav.robot.interface.Robot` of a bridged base: the newest readings
    received, and ``/cmd_vel`` out."""

    def __init__(self, client: RosbridgeClient, config: BridgeConfig, clock: BridgeClock,
                 laser_mount: Pose2D) -> None:
        self._client = client
        self._config = config
        self._clock = clock
        self._laser = laser_mount
        self._lock = threading.Lock()
        self._odometry: Odometry | None = None
        self._scan: LaserScan | None = None
        self._imu: ImuReading | None = None
        self._battery = BatteryState(0.0, 100.0, 0.0, 0.0, False)
        self.ready = threading.Event()

    # -- Robot -------------------------------------------------------------------------------------

    def drive(self, twist: Twist) -> None:
        self._client.publish(self._config.cmd_vel, encode.twist(twist))

    def read_odometry(self) -> Odometry:
        with self._lock:
            if self._odometry is None:
                return Odometry(self._clock.now(), Pose2D(), Twist())
            return self._odometry

    def read_scan(self) -> LaserScan | None:
        return self._scan

    def read_imu(self) -> ImuReading | None:
        return self._imu

    def read_battery(self) -> BatteryState:
        return self._battery

    def estop_pressed(self) -> bool:
        """The standard driver topics carry no e-stop: the base's own button stops it."""
        return False

    def read_people(self) -> Sequence[PersonDetection]:
        return ()

    def read_dock(self) -> DockSignals | None:
        """The standard driver topics carry no beacon or dock link."""
        return None

    # -- from the client's thread -----------------------------------------------------------------

    def _stamp(self, message: dict[str, Any]) -> float:
        if self._clock.follows_robot:
            header = message.get("header")
            if isinstance(header, dict):
                return self._clock.robot_time(decode.stamp(header))
        return self._clock.now()

    def on_odometry(self, message: dict[str, Any]) -> None:
        reading = decode.odometry(message, self._stamp(message))
        with self._lock:
            self._odometry = reading
        self.ready.set()

    def on_scan(self, message: dict[str, Any]) -> None:
        self._scan = decode.laser_scan(message, self._stamp(message), self._laser)

    def on_imu(self, message: dict[str, Any]) -> None:
        self._imu = decode.imu(message, self._stamp(message))

    def on_battery(self, message: dict[str, Any]) -> None:
        self._battery = decode.battery_state(message, self._stamp(message))

    def on_tf(self, message: dict[str, Any]) -> None:
        transforms = message.get("transforms")
        for t in transforms if isinstance(transforms, list) else ():
            if (isinstance(t, dict) and t.get("child_frame_id") == self._config.laser_frame
                    and isinstance(t.get("header"), dict)
                    and t["header"].get("frame_id") == self._config.base_frame):
                tr = t.get("transform", {})
                translation = decode.mapping(tr, "translation", "transform")
                self._laser = Pose2D(decode.number(translation, "x", "translation"),
                                     decode.number(translation, "y", "translation"),
                                     decode.yaw(decode.mapping(tr, "rotation", "transform")))


class RosbridgeBackend:
    """A bridged robot for :meth:`RobotRuntime.bridged` (see the module docstring).

    Args:
        config: where the robot is and its names.
        laser_mount: the lidar's pose on the base until the robot's tf says (the profile's).
    """

    def __init__(self, config: BridgeConfig, laser_mount: Pose2D = Pose2D()) -> None:  # noqa: B008
        self.config = config
        self.clock = BridgeClock()
        self.client = RosbridgeClient(config.url, reconnect_min=config.reconnect_min,
                                      reconnect_max=config.reconnect_max,
                                      silence_timeout=config.silence_timeout,
                                      on_state=self._on_state)
        self.robot = RosbridgeRobot(self.client, config, self.clock, laser_mount)
        self._last_step = 0.0
        c, r = self.client, self.robot
        c.subscribe(config.clock, "rosgraph_msgs/Clock", self._on_clock)
        c.subscribe(config.odom, "nav_msgs/Odometry", r.on_odometry, queue_length=1)
        c.subscribe(config.scan, "sensor_msgs/LaserScan", r.on_scan, queue_length=1)
        c.subscribe(config.imu, "sensor_msgs/Imu", r.on_imu, queue_length=1)
        c.subscribe(config.battery, "sensor_msgs/BatteryState", r.on_battery, queue_length=1)
        c.subscribe(config.tf_static, "tf2_msgs/TFMessage", r.on_tf, queue_length=10)
        c.advertise(config.cmd_vel, "geometry_msgs/Twist")
        self._clock_seen = threading.Event()

    @property
    def physics_period(self) -> float:
        return self.config.physics_period

    @property
    def connected(self) -> bool:
        return self.client.connected

    def wait_ready(self, timeout: float) -> bool:
        """Wait for the first odometry, then decide the clock (see the module docstring).

        Returns:
            Whether odometry came within ``timeout`` wall seconds.
        """
        if not self.robot.ready.wait(timeout):
            return False
        robot_clock = self.config.use_robot_clock and self._clock_seen.wait(
            self.config.clock_grace)
        self.clock.decide(robot_clock)
        self._last_step = self.clock.now()
        return True

    def step(self) -> None:
        period = self.config.physics_period
        target = self._last_step + period
        self.clock.wait_until(target, MAX_WAIT)
        now = self.clock.now()
        if now >= target:  # a period has passed (after a jump of the clock: go on from now)
            self._last_step = target if now < target + period else now

    def close(self) -> None:
        self.robot.drive(Twist())
        self.client.close()

    def _on_state(self, connected: bool) -> None:
        if connected:
            self.clock.back()
        else:
            self.clock.away()

    def _on_clock(self, message: dict[str, Any]) -> None:
        clock = message.get("clock")
        if isinstance(clock, dict):
            self._clock_seen.set()
            self.clock.tick_robot(decode.stamp(clock, "clock"))
