"""The robot's sensor streams on the ROS graph, at their rates on the runtime's clock.

Two sets, from the same readings:

* the androidmsg interface's streams (ros1-nav-iface §1.11-1.15): ``/map`` (latched, when the
  map in use changes), ``/tracked_pose`` 15 Hz, ``/imu/data`` 150 Hz, ``/raw_odom`` 100 Hz,
  ``/scan`` 15 Hz (every new scan);
* what a ROS base driver publishes, so that another polynav (or any ROS program) can drive this
  robot over rosbridge (:mod:`polynav.robot.rosbridge`): ``/odom`` and ``/imu`` at the physics
  rate, ``/tf`` (odom -> base_link, and map -> odom while localized), ``/tf_static``
  (base_link -> laser, latched), ``/battery_state`` 1 Hz and ``/clock`` every step (a bridged
  polynav follows this robot's time as ROS nodes do with ``use_sim_time``); it takes
  ``/cmd_vel`` as the runtime's teleop command, with its dead-man timeout.

Everything runs in a step listener on the runtime's loop, after each physics step. A stream
faster than the physics rate (the simulator steps at 50 Hz) sends every message that fell due
since the last step, each stamped with its own time, the pose and yaw carried forward from the
last reading by the measured velocity (docs/decisions.md, "rosbridge streams above the physics
rate"). A message is built only while someone subscribes (:meth:`Graph.wanted`).
"""

from __future__ import annotations

import logging
import math
import threading
from collections.abc import Callable
from dataclasses import dataclass

from polynav.errors import PolynavError
from polynav.geometry import Pose2D, wrap_angle
from polynav.protocols.ros_graph import Graph, Message, RosError, Subscription, Topic
from polynav.robot.interface import ImuReading, Odometry
from polynav.rosmsg import decode, encode
from polynav.runtime.robot_runtime import RobotRuntime

log = logging.getLogger(__name__)

_EPS = 1e-9

MAP = Topic("/map", "nav_msgs/OccupancyGrid", latched=True)
TRACKED_POSE = Topic("/tracked_pose", "geometry_msgs/PoseStamped")
IMU_DATA = Topic("/imu/data", "sensor_msgs/Imu")
RAW_ODOM = Topic("/raw_odom", "nav_msgs/Odometry")
SCAN = Topic("/scan", "sensor_msgs/LaserScan")
ODOM = Topic("/odom", "nav_msgs/Odometry")
IMU = Topic("/imu", "sensor_msgs/Imu")
TF = Topic("/tf", "tf2_msgs/TFMessage")
TF_STATIC = Topic("/tf_static", "tf2_msgs/TFMessage", latched=True)
BATTERY = Topic("/battery_state", "sensor_msgs/BatteryState")
CLOCK = Topic("/clock", "rosgraph_msgs/Clock")
CMD_VEL_TYPE = "geometry_msgs/Twist"

#: Stream rates [Hz of the runtime's clock] (ros1-nav-iface §0.5); 0: every physics step.
RATES = {TRACKED_POSE.name: 15.0, IMU_DATA.name: 150.0, RAW_ODOM.name: 100.0,
         BATTERY.name: 1.0, ODOM.name: 0.0, IMU.name: 0.0, TF.name: 0.0, CLOCK.name: 0.0}


@dataclass(frozen=True, slots=True)
class Frames:
    """The tf frame names of the streams (ROS's defaults)."""

    map: str = "map"
    odom: str = "odom"
    base: str = "base_link"
    laser: str = "laser"
    imu: str = "imu_link"


class _Schedule:
    """When a stream's next message is due, on the runtime's clock."""

    def __init__(self, rate: float, start: float) -> None:
        self.period = 1.0 / rate if rate > 0 else 0.0
        self.due = start

    def times(self, now: float) -> list[float]:
        """The stamps of the messages due up to ``now`` (at most one second's worth: after
        a jump of the clock the stream goes on from now, not with a burst)."""
        if self.period == 0.0:
            return [now]
        if self.due < now - 1.0:
            self.due = now
        out = []
        while self.due <= now + _EPS:
            out.append(self.due)
            self.due += self.period
        return out


class RobotStreams:
    """The streams of one runtime on one graph (see the module docstring)."""

    def __init__(self, graph: Graph, runtime: RobotRuntime, frames: Frames) -> None:
        self._graph = graph
        self._runtime = runtime
        self._frames = frames
        now = runtime.now()
        self._schedules = {name: _Schedule(rate, now) for name, rate in RATES.items()}
        self._seq: dict[str, int] = {}
        self._last_scan: float | None = None
        self._map_key: object = None
        self._map_lock = threading.Lock()

    def declare(self) -> None:
        for topic in (MAP, TRACKED_POSE, IMU_DATA, RAW_ODOM, SCAN, ODOM, IMU, TF, TF_STATIC,
                      BATTERY, CLOCK):
            self._graph.add_topic(topic)
        self._graph.add_subscription(Subscription("/cmd_vel", CMD_VEL_TYPE, self._cmd_vel))
        scan = self._runtime.robot.read_scan()
        laser = scan.sensor_pose if scan is not None else Pose2D()
        self._graph.publish(TF_STATIC.name, encode.tf_message([encode.transform_stamped(
            0, self._runtime.now(), self._frames.base, self._frames.laser, laser)]))

    # -- on the runtime's loop ----------------------------------------------------------------

    def on_step(self, now: float) -> None:
        robot = self._runtime.robot
        graph = self._graph
        odometry: Odometry | None = None
        self._check_map()
        for topic in (ODOM, RAW_ODOM, TF):
            due = self._schedules[topic.name].times(now)
            if not graph.wanted(topic.name):
                continue
            odometry = odometry or robot.read_odometry()
            for stamp in due:
                if topic is TF:
                    graph.publish(TF.name, self._tf(odometry, stamp))
                else:
                    graph.publish(topic.name, encode.odometry(
                        self._next(topic.name), _at(odometry, stamp), self._frames.odom,
                        self._frames.base, _pose_at(odometry, stamp)))
        for topic in (IMU, IMU_DATA):
            due = self._schedules[topic.name].times(now)
            if not graph.wanted(topic.name) or not due:
                continue
            reading = robot.read_imu()
            if reading is None:
                continue
            for stamp in due:
                dt = max(0.0, stamp - reading.stamp)
                graph.publish(topic.name, encode.imu(
                    self._next(topic.name), _imu_at(reading, stamp), self._frames.imu,
                    wrap_angle(reading.yaw + reading.angular_velocity * dt)))
        due = self._schedules[TRACKED_POSE.name].times(now)
        if due and graph.wanted(TRACKED_POSE.name):
            snap = self._runtime.status()
            for stamp in due:
                graph.publish(TRACKED_POSE.name, encode.pose_stamped(
                    self._next(TRACKED_POSE.name), stamp, self._frames.map, snap.pose))
        if graph.wanted(SCAN.name):
            scan = robot.read_scan()
            if scan is not None and scan.stamp != self._last_scan:
                self._last_scan = scan.stamp
                graph.publish(SCAN.name, encode.laser_scan(self._next(SCAN.name), scan,
                                                           self._frames.laser))
        if self._schedules[BATTERY.name].times(now) and graph.wanted(BATTERY.name):
            graph.publish(BATTERY.name, encode.battery_state(self._next(BATTERY.name),
                                                             robot.read_battery()))
        # The clock last: a follower that wakes on it has this step's readings already.
        if graph.wanted(CLOCK.name):
            graph.publish(CLOCK.name, encode.clock(now))

    def _tf(self, odometry: Odometry, stamp: float) -> Message:
        f = self._frames
        pose = _pose_at(odometry, stamp)
        transforms = [encode.transform_stamped(self._next(TF.name), stamp, f.odom, f.base, pose)]
        snap = self._runtime.status()
        if snap.localization_state == "tracking" and snap.frame == "map":
            map_to_odom = snap.pose.compose(odometry.pose.inverse())
            transforms.append(encode.transform_stamped(self._next(TF.name), stamp, f.map,
                                                       f.odom, map_to_odom))
        return encode.tf_message(transforms)

    def _check_map(self) -> None:
        snap = self._runtime.status()
        key = (snap.map, snap.floor) if snap.map is not None else (None, snap.floor)
        if key == self._map_key:
            return
        self._map_key = key
        # Reading a map from the store is slow: not on the loop.
        threading.Thread(target=self._publish_map, args=(key, snap.stamp), daemon=True,
                         name="polynav-rosbridge-map").start()

    def _publish_map(self, key: tuple[str | None, str], stamp: float) -> None:
        with self._map_lock:
            if key != self._map_key:
                return  # a newer map is on its way
            name, floor = key
            store = self._runtime.store
            try:
                if name is None:
                    name = store.floor(floor).map_name
                grid = store.load_map(name)
            except PolynavError as exc:
                log.debug("rosbridge: no map to publish for %s: %s", key, exc)
                return
            self._graph.publish(MAP.name, encode.occupancy_grid(self._next(MAP.name), stamp,
                                                                grid, self._frames.map))

    # -- from clients -------------------------------------------------------------------------

    def _cmd_vel(self, message: Message) -> None:
        try:
            twist = decode.twist(message, "/cmd_vel")
        except ValueError as exc:
            raise RosError(str(exc)) from None
        try:
            self._runtime.teleop(twist.linear, twist.angular)
        except PolynavError as exc:
            raise RosError(f"/cmd_vel: {exc}") from None

    def _next(self, name: str) -> int:
        seq = self._seq.get(name, 0)
        self._seq[name] = seq + 1
        return seq


def _pose_at(odometry: Odometry, stamp: float) -> Pose2D:
    """The odometry pose carried forward to ``stamp`` by the measured velocity."""
    dt = max(0.0, stamp - odometry.stamp)
    if dt == 0.0:
        return odometry.pose
    p, t = odometry.pose, odometry.twist
    mid = p.theta + 0.5 * t.angular * dt
    return Pose2D(p.x + t.linear * dt * math.cos(mid), p.y + t.linear * dt * math.sin(mid),
                  wrap_angle(p.theta + t.angular * dt))


def _at(odometry: Odometry, stamp: float) -> Odometry:
    return Odometry(stamp, odometry.pose, odometry.twist)


def _imu_at(reading: ImuReading, stamp: float) -> ImuReading:
    return ImuReading(stamp, reading.yaw, reading.angular_velocity, reading.linear_acceleration)


def add_robot_topics(graph: Graph, runtime: RobotRuntime,
                     frames: Frames | None = None) -> Callable[[], None]:
    """Declare the streams and ``/cmd_vel`` on ``graph`` and publish from ``runtime``'s loop;
    returns the function that stops publishing."""
    streams = RobotStreams(graph, runtime, frames or Frames())
    streams.declare()
    return runtime.add_step_listener(streams.on_step)
