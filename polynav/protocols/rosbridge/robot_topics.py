"""The robot's sensor streams on the ROS graph, at their rates on the runtime's clock.

Two sets, from the same readings:

* the androidmsg interface's streams (ros1-nav-iface §1.11-1.15): ``/map`` (latched: at
  start, when the map navigation runs on changes or is saved again, and while mapping the
  growing map every :data:`LIVE_MAP_PERIOD`), ``/tracked_pose`` 15 Hz, ``/imu/data`` 150 Hz,
  ``/raw_odom`` 100 Hz, ``/scan`` 15 Hz (every new scan);
* what a ROS base driver publishes, so that another polynav (or any ROS program) can drive this
  robot over rosbridge (:mod:`polynav.robot.rosbridge`): ``/odom`` and ``/imu`` at the physics
  rate, ``/tf`` (odom -> base_link, and map -> odom while localized), ``/tf_static``
  (base_link -> laser, latched), ``/battery_state`` 1 Hz and ``/clock`` every step (a bridged
  polynav follows this robot's time as ROS nodes do with ``use_sim_time``); it takes
  ``/cmd_vel`` as the runtime's teleop command, with its dead-man timeout.

Everything runs in a step listener on the runtime's loop, after each physics step. A stream
faster than the physics rate (the simulator steps at 50 Hz) sends every message that fell due
since the last step, each stamped with its own time and carrying the step's reading to that
time by the measured velocity (docs/decisions.md, "rosbridge streams above the physics rate").
A message is built only while someone subscribes (:meth:`Graph.wanted`). ``/map`` is read from
the store, or rendered from the SLAM while mapping, on a thread of its own
(:class:`MapStream`): the loop only says when to look.
"""

from __future__ import annotations

import logging
import math
import threading
from collections.abc import Callable
from dataclasses import dataclass

from polynav.errors import PolynavError
from polynav.geometry import Pose2D, Twist, wrap_angle
from polynav.protocols.ros_graph import Graph, Message, RosError, Subscription, Topic
from polynav.robot.interface import ImuReading, Odometry
from polynav.rosmsg import decode, encode
from polynav.runtime.robot_runtime import RobotRuntime
from polynav.store.site_store import SiteStore

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

#: The longest a reading is carried to a message's stamp by its velocity [s]: further (a
#: robot whose readings stopped coming) the reading goes out as it is.
MAX_CARRY = 0.1
#: How often the map in use is looked at for a new save [s of the runtime's clock].
MAP_CHECK_PERIOD = 1.0
#: How often the growing map is sent while mapping [s of the runtime's clock]: rendering it
#: takes the SLAM's time, and a client watching the map grow needs no more.
LIVE_MAP_PERIOD = 2.0


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


def carry(pose: Pose2D, twist: Twist, dt: float) -> Pose2D:
    """``pose`` moved ``dt`` seconds along the arc of the body velocity ``twist`` (backwards
    for a negative ``dt``; at most :data:`MAX_CARRY` either way)."""
    dt = max(-MAX_CARRY, min(MAX_CARRY, dt))
    if dt == 0.0:
        return pose
    mid = pose.theta + 0.5 * twist.angular * dt
    step = twist.linear * dt
    return Pose2D(pose.x + step * math.cos(mid), pose.y + step * math.sin(mid),
                  wrap_angle(pose.theta + twist.angular * dt))


def carry_yaw(reading: ImuReading, stamp: float) -> float:
    """The IMU's yaw carried from its reading to ``stamp`` by the yaw rate (as :func:`carry`)."""
    dt = max(-MAX_CARRY, min(MAX_CARRY, stamp - reading.stamp))
    return wrap_angle(reading.yaw + reading.angular_velocity * dt)


class RobotStreams:
    """The streams of one runtime on one graph (see the module docstring)."""

    def __init__(self, graph: Graph, runtime: RobotRuntime, frames: Frames) -> None:
        self._graph = graph
        self._runtime = runtime
        self._frames = frames
        now = runtime.now()
        self._schedules = {name: _Schedule(rate, now) for name, rate in RATES.items()}
        self._seq = _Sequences()
        self._last_scan: float | None = None
        self.map = MapStream(graph, runtime, frames.map, self._seq)

    def declare(self) -> None:
        for topic in (MAP, TRACKED_POSE, IMU_DATA, RAW_ODOM, SCAN, ODOM, IMU, TF, TF_STATIC,
                      BATTERY, CLOCK):
            self._graph.add_topic(topic)
        self._graph.add_subscription(Subscription("/cmd_vel", CMD_VEL_TYPE, self._cmd_vel))
        scan = self._runtime.robot.read_scan()
        laser = scan.sensor_pose if scan is not None else Pose2D()
        self._graph.publish(TF_STATIC.name, encode.tf_message([encode.transform_stamped(
            0, self._runtime.now(), self._frames.base, self._frames.laser, laser)]))
        self.map.start()

    def close(self) -> None:
        self.map.close()

    # -- on the runtime's loop ----------------------------------------------------------------

    def on_step(self, now: float) -> None:
        self.map.on_step(now)
        self._odometry_streams(now)
        self._imu_streams(now)
        self._tracked_pose(now)
        robot = self._runtime.robot
        graph = self._graph
        if graph.wanted(SCAN.name):
            scan = robot.read_scan()
            if scan is not None and scan.stamp != self._last_scan:
                self._last_scan = scan.stamp
                graph.publish(SCAN.name, encode.laser_scan(self._seq.next(SCAN.name), scan,
                                                           self._frames.laser))
        if self._schedules[BATTERY.name].times(now) and graph.wanted(BATTERY.name):
            graph.publish(BATTERY.name, encode.battery_state(self._seq.next(BATTERY.name),
                                                             robot.read_battery()))
        # The clock last: a follower that wakes on it has this step's readings already.
        if graph.wanted(CLOCK.name):
            graph.publish(CLOCK.name, encode.clock(now))

    def _odometry_streams(self, now: float) -> None:
        graph = self._graph
        odometry: Odometry | None = None
        for topic in (ODOM, RAW_ODOM, TF):
            due = self._schedules[topic.name].times(now)
            if not due or not graph.wanted(topic.name):
                continue
            odometry = odometry or self._runtime.robot.read_odometry()
            if topic is TF:
                map_to_odom = self._map_to_odom(odometry)
                for stamp in due:
                    graph.publish(TF.name, self._tf(odometry, stamp, map_to_odom))
                continue
            for stamp in due:
                graph.publish(topic.name, encode.odometry(
                    self._seq.next(topic.name), Odometry(stamp, odometry.pose, odometry.twist),
                    self._frames.odom, self._frames.base,
                    carry(odometry.pose, odometry.twist, stamp - odometry.stamp)))

    def _imu_streams(self, now: float) -> None:
        reading: ImuReading | None = None
        for topic in (IMU, IMU_DATA):
            due = self._schedules[topic.name].times(now)
            if not due or not self._graph.wanted(topic.name):
                continue
            reading = reading or self._runtime.robot.read_imu()
            if reading is None:
                return
            for stamp in due:
                at = ImuReading(stamp, reading.yaw, reading.angular_velocity,
                                reading.linear_acceleration)
                self._graph.publish(topic.name, encode.imu(
                    self._seq.next(topic.name), at, self._frames.imu, carry_yaw(reading, stamp)))

    def _tracked_pose(self, now: float) -> None:
        due = self._schedules[TRACKED_POSE.name].times(now)
        if not due or not self._graph.wanted(TRACKED_POSE.name):
            return
        # The status is refreshed at the control rate: its pose is carried to each stamp.
        snap = self._runtime.status()
        velocity = Twist(snap.linear, snap.angular)
        for stamp in due:
            self._graph.publish(TRACKED_POSE.name, encode.pose_stamped(
                self._seq.next(TRACKED_POSE.name), stamp, self._frames.map,
                carry(snap.pose, velocity, stamp - snap.stamp)))

    def _map_to_odom(self, odometry: Odometry) -> Pose2D | None:
        """The odometry frame on the map while localized on one (the localization's pose
        carried to the odometry's stamp first, so the two are of the same instant)."""
        snap = self._runtime.status()
        if snap.localization_state != "tracking" or snap.frame != "map":
            return None
        on_map = carry(snap.pose, Twist(snap.linear, snap.angular), odometry.stamp - snap.stamp)
        return on_map.compose(odometry.pose.inverse())

    def _tf(self, odometry: Odometry, stamp: float, map_to_odom: Pose2D | None) -> Message:
        f = self._frames
        pose = carry(odometry.pose, odometry.twist, stamp - odometry.stamp)
        transforms = [encode.transform_stamped(self._seq.next(TF.name), stamp, f.odom, f.base,
                                               pose)]
        if map_to_odom is not None:
            transforms.append(encode.transform_stamped(self._seq.next(TF.name), stamp, f.map,
                                                       f.odom, map_to_odom))
        return encode.tf_message(transforms)

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


class _Sequences:
    """Each topic's header ``seq``, counting from 0 (the loop and the map thread share it)."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._seq: dict[str, int] = {}

    def next(self, name: str) -> int:
        with self._lock:
            seq = self._seq.get(name, 0)
            self._seq[name] = seq + 1
            return seq


class MapStream:
    """``/map``: the map navigation runs on (the floor's map while not navigating), sent when
    it changes or is saved again; while mapping, the map being built, every
    :data:`LIVE_MAP_PERIOD` while someone subscribes.

    Loading a map from the store and rendering the SLAM's map are slow, so they run on a thread
    of its own; the loop's part (:meth:`on_step`) only reads the status and sets a request.
    """

    def __init__(self, graph: Graph, runtime: RobotRuntime, frame_id: str,
                 seq: _Sequences) -> None:
        self._graph = graph
        self._runtime = runtime
        self._frame_id = frame_id
        self._seq = seq
        now = runtime.now()
        self._check = _Schedule(1.0 / MAP_CHECK_PERIOD, now)
        self._live = _Schedule(1.0 / LIVE_MAP_PERIOD, now)
        self._situation: object = None
        self._wake = threading.Condition()
        self._request: tuple[bool, float] | None = None  # (live, stamp)
        self._closed = False
        self._sent: object = None  # what the last message was made of
        self._thread = threading.Thread(target=self._run, daemon=True,
                                        name="polynav-rosbridge-map")

    def start(self) -> None:
        self._ask(self._runtime.status().mode == "mapping", self._runtime.now())
        self._thread.start()

    def close(self) -> None:
        with self._wake:
            self._closed = True
            self._wake.notify()
        if self._thread.is_alive() and self._thread is not threading.current_thread():
            self._thread.join(timeout=10.0)

    def on_step(self, now: float) -> None:
        snap = self._runtime.status()
        live = snap.mode == "mapping"
        situation = (live, snap.map, snap.floor)
        changed = situation != self._situation
        self._situation = situation
        if live:
            if changed:  # mapping began: the first map now, the next a period on
                self._live.due = now + LIVE_MAP_PERIOD
            if (self._live.times(now) or changed) and self._graph.wanted(MAP.name):
                self._ask(True, now)
        elif self._check.times(now) or changed:
            self._ask(False, now)

    def _ask(self, live: bool, stamp: float) -> None:
        with self._wake:
            self._request = (live, stamp)
            self._wake.notify()

    def _run(self) -> None:
        while True:
            with self._wake:
                while self._request is None and not self._closed:
                    self._wake.wait()
                if self._closed:
                    return
                assert self._request is not None
                live, stamp = self._request
                self._request = None
            try:
                self._publish(live, stamp)
            except PolynavError as exc:
                log.debug("rosbridge: no map to publish: %s", exc)
            except Exception:  # the one broad except of the thread: log, keep serving
                log.exception("rosbridge: publishing /map failed")

    def _publish(self, live: bool, stamp: float) -> None:
        if live:
            grid = self._runtime.mapping_map()  # rendered again only after new scans
            if grid is self._sent:
                return
            self._sent = grid
        else:
            snap = self._runtime.status()
            name = snap.map
            if name is None:
                if snap.floor is None:
                    return
                name = self._runtime.store.floor(snap.floor).map_name
            key = (name, self._version(name))
            if isinstance(self._sent, tuple) and self._sent == key:
                return
            grid = self._runtime.store.load_map(name)
            self._sent = key
        self._graph.publish(MAP.name, encode.occupancy_grid(self._seq.next(MAP.name), stamp,
                                                            grid, self._frame_id))

    def _version(self, name: str) -> object:
        """What changes when map ``name`` is saved again (its picture's file name)."""
        store = self._runtime.store
        return store.map_image_path(name) if isinstance(store, SiteStore) else None


def add_robot_topics(graph: Graph, runtime: RobotRuntime,
                     frames: Frames | None = None) -> Callable[[], None]:
    """Declare the streams and ``/cmd_vel`` on ``graph`` and publish from ``runtime``'s loop;
    returns the function that stops publishing."""
    streams = RobotStreams(graph, runtime, frames or Frames())
    streams.declare()
    remove = runtime.add_step_listener(streams.on_step)

    def stop() -> None:
        remove()
        streams.close()

    return stop
