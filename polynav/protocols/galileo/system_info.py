"""System endpoints: information, log, speed and remote control, power, self-test, topics and
ROS parameters (galileo-http-a §3.2, §3.5, §3.9, §3.12: E-03, E-05–E-08, E-22, E-23, E-44,
E-49, E-72, E-73, E-75, E-76).

Decisions (``docs/galileo.md``):

* ``/system/info`` reports the rates the (simulated) sensors publish at: odometry at the physics
  rate, the IMU at its rate; the cameras stream nothing (they take pictures on request), so
  their rates are ``0``. ``slam_type`` is ``"lidar"``.
* ``/system/log`` is the robot's event log (:mod:`polynav.runtime.event_log`): the latest
  runtime events since power-on, oldest first, one line each.
* ``PUT /system/speed`` drives by teleop; the runtime's dead-man stops the robot when no new
  command comes (A-37). ``speed_y`` is refused unless 0: the base is differential.
* ``shutdown`` and ``restart_robot`` power the robot off (and on) through the runtime's power
  cycle; ``restart_novnc`` has no service to restart and answers ``true``.
* ``schedule_manager``: polynav uses no Lagrange scheduling server, so the list is empty.
  ``check_cert``: polynav needs no licence certificate: ``ok``.
* ``/system/topic`` serves the topics polynav has as JSON (``/galileo/status`` and the two
  sensor topics); another topic is a 404.
* ``ros_params`` is a parameter store kept in ``<data>/galileo/ros_params.json``; an unknown
  parameter reads ``null`` (A-38).
"""

from __future__ import annotations

import json
import logging
import os
import tempfile
import threading
from pathlib import Path
from typing import Any

from polynav.errors import InvalidRequest, NotFound, StorageError
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.endpoint import Reply, RouteList
from polynav.protocols.galileo.params import Params
from polynav.protocols.galileo.status import galileo_status
from polynav.protocols.galileo.topics import air_message, env_message

log = logging.getLogger(__name__)

ROUTES = RouteList()

#: self-test field -> the self-check parts that must pass for it.
SELF_TEST_PARTS = {
    "motor_driver": ("motor_core_left", "motor_core_right", "CAN"),
    "camera": ("laser",),  # the simulated camera renders from the lidar
    "charge": ("power_core",),
    "lidar": ("laser",),
    "bluetooth": ("radio_core",),
    "battery": ("power_core",),
}


@ROUTES.get("/system/info", inline=True)
def get_info(ctx: Context, params: Params) -> Reply:
    """E-03: battery, sensor rates, e-stop, charge and loop tasks, identity."""
    snap = ctx.runtime.status()
    return {
        "battery": int(round(snap.battery_percent)),
        "camera_rgb": 0,
        "camera_depth": 0,
        "odom": int(round(1.0 / ctx.runtime.physics_period)),
        "imu": int(round(ctx.runtime.profile.imu.rate)),
        "camera_processed": 0,
        "driver_port": bool(snap.estop_hardware),
        "info": {"version": ctx.version, "code_name": "polynav", "id": ctx.robot_id,
                 "mac": ctx.mac, "port": ctx.config.port},
        "charge": snap.phase == "dock" and snap.navigation_state in ("running", "paused"),
        "loop": snap.patrol_state == "running",
        "slam_type": "lidar",
    }


@ROUTES.get("/system/log")
def get_log(ctx: Context, params: Params) -> Reply:
    """E-05: ``{"log": text}``."""
    return {"log": ctx.runtime.peripherals.event_log.text()}


@ROUTES.get("/system/speed", inline=True)
def get_speed(ctx: Context, params: Params) -> Reply:
    """E-06: measured body speed (``speed_y`` 0 on a differential base)."""
    snap = ctx.runtime.status()
    return {"speed_x": float(snap.linear), "speed_y": 0.0, "speed_angle": float(snap.angular)}


@ROUTES.put("/system/speed", result_errors=True)
def put_speed(ctx: Context, params: Params) -> Reply:
    """E-07: remote control at the given speeds (repeat at about 5 Hz)."""
    speed_x = params.number("speed_x")
    speed_y = params.number("speed_y", 0.0)
    speed_angle = params.number("speed_angle")
    if speed_y != 0.0:
        raise InvalidRequest("speed_y", "this base is differential: it cannot move sideways")
    ctx.runtime.teleop(speed_x, speed_angle)
    return {"result": True}


@ROUTES.get("/system/shutdown", result_errors=True)
def get_shutdown(ctx: Context, params: Params) -> Reply:
    """E-08: power off (after the runtime's notice)."""
    ctx.runtime.device.power.shutdown(reboot=False)
    return {"result": True}


@ROUTES.get("/system/restart_robot", result_errors=True)
def get_restart_robot(ctx: Context, params: Params) -> Reply:
    """E-75: power off and on again."""
    ctx.runtime.device.power.shutdown(reboot=True)
    return {"result": True}


@ROUTES.get("/system/restart_novnc", result_errors=True)
def get_restart_novnc(ctx: Context, params: Params) -> Reply:
    """E-76: polynav runs no noVNC service; nothing to restart."""
    return {"result": True}


@ROUTES.get("/system/schedule_manager", inline=True)
def get_schedule_manager(ctx: Context, params: Params) -> Reply:
    """E-22: the scheduling servers (none)."""
    return []


@ROUTES.get("/system/self_test")
def get_self_test(ctx: Context, params: Params) -> Reply:
    """E-23: each module passes when its parts passed their latest self-check."""
    results = dict(ctx.runtime.device.self_check.results)
    return {
        name: all(p in results and results[p].ok for p in parts)
        for name, parts in SELF_TEST_PARTS.items()
    }


@ROUTES.get("/system/check_cert", inline=True)
def get_check_cert(ctx: Context, params: Params) -> Reply:
    """E-49: no licence is needed."""
    return {"status": "ok"}


@ROUTES.get("/system/topic")
def get_topic(ctx: Context, params: Params) -> Reply:
    """E-44: a topic's latest message as JSON."""
    name = params.text("topic_name")
    if name == "/galileo/status":
        return galileo_status(ctx)
    if name in ("/bw_env_sensors/EnvSensorData", "/bw_env_sensors/AirSensorData"):
        env, air = ctx.runtime.peripherals.environment()
        if name.endswith("EnvSensorData"):
            return env_message(env)
        return air_message(air)
    raise NotFound("topic", name)


class ParamStore:
    """ROS-style parameters in a JSON file, written atomically."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self.lock = threading.Lock()

    def load(self) -> dict[str, Any]:
        if not self.path.exists():
            return {}
        try:
            data = json.loads(self.path.read_text("utf-8"))
        except ValueError as exc:
            raise StorageError(f"{self.path}: {exc}") from exc
        return dict(data) if isinstance(data, dict) else {}

    def set(self, name: str, value: Any) -> None:
        with self.lock:
            data = self.load()
            data[name] = value
            self.path.parent.mkdir(parents=True, exist_ok=True)
            fd, tmp = tempfile.mkstemp(prefix=".ros_params.", dir=self.path.parent)
            try:
                with os.fdopen(fd, "w", encoding="utf-8") as f:
                    json.dump(data, f, ensure_ascii=False)
                    f.flush()
                    os.fsync(f.fileno())
                os.replace(tmp, self.path)
            except OSError as exc:
                Path(tmp).unlink(missing_ok=True)
                raise StorageError(f"{self.path}: {exc}") from exc


def _params(ctx: Context) -> ParamStore:
    return ctx.state("galileo.ros_params",
                     lambda: ParamStore(ctx.data_dir / "galileo" / "ros_params.json"))


def _param_name(params: Params) -> str:
    name = params.text("param")
    if not name.strip():
        raise InvalidRequest("param", "must not be empty")
    return str(name)


@ROUTES.get("/system/ros_params")
def get_ros_params(ctx: Context, params: Params) -> Reply:
    """E-72: ``{<param>: value}`` (``null`` when never set)."""
    name = _param_name(params)
    return {name: _params(ctx).load().get(name)}


@ROUTES.put("/system/ros_params")
def put_ros_params(ctx: Context, params: Params) -> Reply:
    """E-73: set a parameter to any JSON value."""
    name = _param_name(params)
    if "value" not in params.values:
        raise InvalidRequest("value", "required parameter is missing")
    value = params.values["value"]
    try:
        json.dumps(value)
    except (TypeError, ValueError) as exc:
        raise InvalidRequest("value", "must be a JSON value") from exc
    _params(ctx).set(name, value)
    return {name: value}


