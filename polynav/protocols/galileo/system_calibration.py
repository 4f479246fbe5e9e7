"""Calibration and software-update endpoints (galileo-http-a §3.3, §3.4: E-09–E-21, E-51,
E-52).

The calibrations are the robot's procedures (:mod:`polynav.robot.sim.devices.calibration`):
camera ``start`` -> ``CALIBRATING`` -> (the robot is driven round a loop) -> ``CALIBRATED`` ->
``complete``; lidar the same after a committed camera calibration. Camera ``start``/``cancel``
answer ``result`` as a string (A-07); an idle camera calibration reads ``FREE`` and
``accuracy`` is present only when ``CALIBRATED`` (A-08). Starting while navigating or mapping is
refused (A-05). The updater has nothing newer than the running version: ``need_update`` is
false and ``update/start`` is refused with the reason. ``use_dev`` (the preview channel) is
kept per adapter; there is no preview channel to switch to, so it only records the choice.
"""

from __future__ import annotations

from typing import Any

from polynav.errors import Conflict, InvalidRequest
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.endpoint import Reply, RouteList
from polynav.protocols.galileo.params import Params
from polynav.protocols.galileo.system_replies import OK, refused, string_reply
from polynav.robot.devices import CalibrationStatus

ROUTES = RouteList()


@ROUTES.get("/system/calibrate_imu", result_errors=True)
def get_calibrate_imu(ctx: Context, params: Params) -> Reply:
    """E-09: start the gyroscope calibration (the robot must stand still)."""
    ctx.runtime.peripherals.calibrate_imu()
    return {"result": True}


def _calibration_status(ctx: Context, which: str) -> dict[str, Any]:
    status, accuracy = ctx.runtime.peripherals.calibration(which)
    body: dict[str, Any] = {"status": status.value}
    if status is CalibrationStatus.CALIBRATED:
        body["accuracy"] = float(accuracy)
    return body


@ROUTES.get("/system/calibrate_camera/start")
def get_camera_start(ctx: Context, params: Params) -> Reply:
    """E-10: ``{"result": "ok"}``; ``camera_id`` absent, 0 or 1 (A-06)."""
    camera_id = params.integer("camera_id", None)
    if camera_id not in (None, 0, 1):
        return refused("result", InvalidRequest("camera_id", f"must be 0 or 1, got {camera_id}"))
    return string_reply("result", lambda: ctx.runtime.peripherals.start_calibration("camera"))


@ROUTES.get("/system/calibrate_camera/cancel")
def get_camera_cancel(ctx: Context, params: Params) -> Reply:
    """E-11: ``{"result": "ok"}``; refused when nothing runs."""
    return string_reply("result", lambda: _cancel(ctx, "camera"))


@ROUTES.get("/system/calibrate_camera/status")
def get_camera_status(ctx: Context, params: Params) -> Reply:
    """E-12: ``FREE``, ``CALIBRATING`` or ``CALIBRATED`` (+ ``accuracy``)."""
    return _calibration_status(ctx, "camera")


@ROUTES.get("/system/calibrate_camera/complete")
def get_camera_complete(ctx: Context, params: Params) -> Reply:
    """E-13: commit; only when CALIBRATED."""
    return string_reply("status", lambda: ctx.runtime.peripherals.complete_calibration("camera"))


@ROUTES.get("/system/calibrate_laser/start")
def get_laser_start(ctx: Context, params: Params) -> Reply:
    """E-14: after a committed camera calibration."""
    return string_reply("status", lambda: ctx.runtime.peripherals.start_calibration("lidar"))


@ROUTES.get("/system/calibrate_laser/complete")
def get_laser_complete(ctx: Context, params: Params) -> Reply:
    """E-15: commit; only when CALIBRATED."""
    return string_reply("status", lambda: ctx.runtime.peripherals.complete_calibration("lidar"))


@ROUTES.get("/system/calibrate_laser/cancel")
def get_laser_cancel(ctx: Context, params: Params) -> Reply:
    """E-16."""
    return string_reply("status", lambda: _cancel(ctx, "lidar"))


@ROUTES.get("/system/calibrate_laser/status")
def get_laser_status(ctx: Context, params: Params) -> Reply:
    """E-17: ``FREE``, ``CALIBRATING`` or ``CALIBRATED``."""
    return _calibration_status(ctx, "lidar")


def _cancel(ctx: Context, which: str) -> None:
    if not ctx.runtime.peripherals.cancel_calibration(which):
        raise Conflict(f"no {which} calibration is running")


# -- software update ---------------------------------------------------------------------------


@ROUTES.get("/system/update/check")
def get_update_check(ctx: Context, params: Params) -> Reply:
    """E-18: ``{"status": "ok", "need_update": false}``."""
    available = ctx.runtime.peripherals.devices.software_update.check()
    return {"status": OK, "need_update": available is not None}


@ROUTES.get("/system/update/start")
def get_update_start(ctx: Context, params: Params) -> Reply:
    """E-19: refused: there is nothing to update to."""
    return string_reply("status", ctx.runtime.peripherals.devices.software_update.start)


@ROUTES.get("/system/update/cancel")
def get_update_cancel(ctx: Context, params: Params) -> Reply:
    """E-20: refused when no update runs."""

    def cancel() -> None:
        if not ctx.runtime.peripherals.devices.software_update.cancel():
            raise Conflict("no update is running")

    return string_reply("status", cancel)


@ROUTES.get("/system/update/log")
def get_update_log(ctx: Context, params: Params) -> Reply:
    """E-21: the updater's log; ``is_complete`` true (no update runs)."""
    return {"status": OK, "log": ctx.runtime.peripherals.devices.software_update.log(),
            "is_complete": True}


@ROUTES.get("/system/use_dev", inline=True)
def get_use_dev(ctx: Context, params: Params) -> Reply:
    """E-51."""
    return {"use_dev": bool(ctx.state("galileo.use_dev", lambda: [False])[0])}


@ROUTES.put("/system/use_dev")
def put_use_dev(ctx: Context, params: Params) -> Reply:
    """E-52: ``{"use_dev": <the setting>}``."""
    value = params.boolean("use_dev")
    ctx.state("galileo.use_dev", lambda: [False])[0] = value
    return {"use_dev": value}

