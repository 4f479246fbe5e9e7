"""The WebSocket topics: what each one sends (ROS messages as JSON) and at what rate.

Galileo's WebSocket serves ROS topics by name (galileo-tasks-bt-ws §8). polynav serves the ones
a client of a navigation robot reads, in the ROS message's JSON form (field names of the ROS
message, nested messages as objects, ``header`` = ``{seq, stamp: {secs, nsecs}, frame_id}``):

==================================  ====================================  ==================
topic                               message                               rate [Hz, runtime]
==================================  ====================================  ==================
``/galileo/status``                 GalileoStatus (galileo-http-a §1.6)   10 (runtime status)
``/odom``                           ``nav_msgs/Odometry``                 20
``/scan``                           ``sensor_msgs/LaserScan``             10
``/tracked_pose``                   ``geometry_msgs/PoseStamped``         10
``/map``                            ``nav_msgs/OccupancyGrid``            on subscribe and on
                                                                          a change of map
``/bw_env_sensors/EnvSensorData``   env sensor reading                    1
``/bw_env_sensors/AirSensorData``   air sensor reading                    1
==================================  ====================================  ==================

``/cmd_vel`` takes ``geometry_msgs/Twist`` messages from the client (teleop; 6.2.1+),
``/galileo/cmds`` ``GalileoNativeCmds`` (one native command, galileo-wire-protocols §2.2). Times
are the runtime's clock (simulated time in simulation). A topic whose source is missing on this
robot sends nothing.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from polynav.errors import InvalidRequest, PolynavError
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.diagnostics import diagnostics
from polynav.protocols.galileo.native.control import native_control
from polynav.protocols.galileo.native.ros_message import decode_native_cmds
from polynav.protocols.galileo.status import galileo_status
from polynav.robot.devices import AirReading, EnvReading
from polynav.rosmsg import decode, encode

log = logging.getLogger(__name__)

Render = Callable[[Context, int], dict[str, Any] | None]


@dataclass(frozen=True, slots=True)
class Topic:
    """A topic the WebSocket serves.

    Attributes:
        name: the path (``/galileo/status``).
        rate: messages per second of the runtime's clock; 0: only when ``changed`` says so.
        render: the message (given the connection's sequence number), ``None`` when there is
            nothing to send now.
        changed: for ``rate == 0``: a key that changes when a new message is due.
        publish: handles a message the client sends (``/cmd_vel``).
    """

    name: str
    rate: float
    render: Render | None = None
    changed: Callable[[Context], object] | None = None
    publish: Callable[[Context, Any], None] | None = None


def _status(ctx: Context, seq: int) -> dict[str, Any]:
    return galileo_status(ctx)


def _odom(ctx: Context, seq: int) -> dict[str, Any] | None:
    runtime = ctx.runtime
    try:
        odom = runtime.run_between_ticks(runtime.robot.read_odometry)
    except PolynavError as exc:  # powered off
        log.debug("galileo: no odometry: %s", exc)
        return None
    return encode.odometry(seq, odom)


def _scan(ctx: Context, seq: int) -> dict[str, Any] | None:
    runtime = ctx.runtime
    try:
        scan = runtime.run_between_ticks(runtime.robot.read_scan)
    except PolynavError as exc:
        log.debug("galileo: no scan: %s", exc)
        return None
    if scan is None:
        return None
    return encode.laser_scan(seq, scan, scan_time=0.1)


def _tracked_pose(ctx: Context, seq: int) -> dict[str, Any]:
    snap = ctx.runtime.status()
    return encode.pose_stamped(seq, snap.stamp, "map", snap.pose)


def _map_key(ctx: Context) -> object:
    snap = ctx.runtime.status()
    return snap.map or snap.floor


def _map(ctx: Context, seq: int) -> dict[str, Any] | None:
    snap = ctx.runtime.status()
    name = snap.map
    if name is None and snap.floor is not None:
        name = ctx.store.floor(snap.floor).map_name
    if name is None:
        return None
    return encode.occupancy_grid(seq, snap.stamp, ctx.store.load_map(name))


def env_message(reading: EnvReading) -> dict[str, float]:
    """``/bw_env_sensors/EnvSensorData`` (galileo-tasks-bt-ws §8.1): the documented fields
    only, as the vendor's message has no header."""
    return {"temperature": reading.temperature, "rh": reading.humidity,
            "smoke": reading.smoke, "pm1_0": reading.pm1_0, "pm2_5": reading.pm2_5,
            "pm10": reading.pm10, "lel": reading.lel, "noise": reading.noise}


def air_message(reading: AirReading) -> dict[str, float]:
    """``/bw_env_sensors/AirSensorData``: ``co2`` in ppm (the source's "smoke ppm" is a copy
    error, A-20)."""
    return {"temperature": reading.temperature, "rh": reading.humidity, "co2": reading.co2,
            "illuminance": reading.illuminance}


def _env(ctx: Context, seq: int) -> dict[str, Any]:
    return env_message(ctx.runtime.peripherals.environment()[0])


def _air(ctx: Context, seq: int) -> dict[str, Any]:
    return air_message(ctx.runtime.peripherals.environment()[1])


def _native_cmds(ctx: Context, message: Any) -> None:
    """A ``GalileoNativeCmds``: one native command (galileo-wire-protocols §2.2)."""
    try:
        payload = decode_native_cmds(message)
    except ValueError as exc:
        diagnostics(ctx).count("ros.bad_message")
        raise InvalidRequest("/galileo/cmds", str(exc)) from None
    native_control(ctx).apply(payload)


def _cmd_vel(ctx: Context, message: Any) -> None:
    """A ``geometry_msgs/Twist``: ``linear.x`` [m/s] and ``angular.z`` [rad/s] drive."""
    try:
        twist = decode.twist(message)
    except ValueError as exc:
        raise InvalidRequest("cmd_vel", str(exc)) from None
    ctx.runtime.teleop(twist.linear, twist.angular)


TOPICS: dict[str, Topic] = {
    t.name: t
    for t in (
        Topic("/galileo/status", 10.0, _status),
        Topic("/odom", 20.0, _odom),
        Topic("/scan", 10.0, _scan),
        Topic("/tracked_pose", 10.0, _tracked_pose),
        Topic("/map", 0.0, _map, changed=_map_key),
        Topic("/cmd_vel", 0.0, publish=_cmd_vel),
        Topic("/galileo/cmds", 0.0, publish=_native_cmds),
        Topic("/bw_env_sensors/EnvSensorData", 1.0, _env),
        Topic("/bw_env_sensors/AirSensorData", 1.0, _air),
    )
}

