"""ONVIF network cameras (galileo-http-a §3.17: E-77–E-85).

The site's camera is simulated (:mod:`polynav.robot.sim.devices.onvif`): it stands at an
address of the documentation range and is never contacted over the network. Every camera call
names it by ``ip`` (empty: the first camera found, A-42), ``port``, ``username`` and
``password``; an unknown address or wrong credentials are refused (HTTP 400) before anything
moves. ``GET /system/onvif_cameras`` without parameters lists the cameras as a bare array, and
with them answers the camera's profiles as text (A-21), in the Python-repr form the vendor's
robot prints. ``move_speed`` answers ``success`` and the others ``ok`` (A-26). A snapshot is
saved with the photos and named by its file-system path (``/home/xiaoqiang/Pictures/...``), so
the file API fetches it. The thermometry reads the room's temperature (the environment
sensor) over two measuring rules, in the Hikvision ISAPI shape of the example.
"""

from __future__ import annotations

from typing import Any

from starlette.responses import PlainTextResponse

from polynav.errors import InvalidRequest
from polynav.protocols.galileo import fs
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.endpoint import Reply, RouteList
from polynav.protocols.galileo.params import Params
from polynav.protocols.galileo.system_replies import OK
from polynav.robot.devices import PtzCamera, PtzPose

ROUTES = RouteList()


def _camera(ctx: Context, params: Params) -> PtzCamera:
    camera = ctx.runtime.peripherals.devices.ptz_camera
    camera.check_login(params.text("ip"), params.integer("port"), params.text("username"),
                       params.text("password"))
    return camera


def _channel(params: Params) -> int:
    channel = params.integer("channel", 1)
    if channel != 1:
        raise InvalidRequest("channel", f"the camera has channel 1 only, got {channel}")
    return int(channel)


def profiles(camera: PtzCamera) -> list[dict[str, Any]]:
    """The camera's media profile, as the vendor's robot reads it from ONVIF."""
    return [{
        "Name": "Stream_101",
        "VideoSourceConfiguration": {
            "Name": "VideoSourceConfig_1", "UseCount": 1, "SourceToken": "VideoSource_1",
            "Bounds": {"x": 0, "y": 0, "width": 320, "height": 240}, "token":
                "VideoSourceToken_1",
        },
        "VideoEncoderConfiguration": {
            "Name": "VideoEncoder_101", "UseCount": 1, "Encoding": "JPEG",
            "Resolution": {"Width": 320, "Height": 240}, "Quality": 3.0,
            "RateControl": {"FrameRateLimit": 2, "EncodingInterval": 1, "BitrateLimit": 512},
            "token": "VideoEncoderToken_101",
        },
        "PTZConfiguration": {
            "Name": "PTZ", "NodeToken": "PTZNodeToken",
            "PanTiltLimits": {"XRange": {"Min": -1.0, "Max": 1.0},
                              "YRange": {"Min": -1.0, "Max": 1.0}},
            "ZoomLimits": {"XRange": {"Min": 0.0, "Max": 1.0}},
            "Presets": sorted(camera.presets()),
        },
        "token": "Profile_101",
    }]


@ROUTES.get("/system/onvif_cameras")
def get_onvif_cameras(ctx: Context, params: Params) -> Reply:
    """E-77 (no parameters: the cameras) or E-78 (a camera's profiles, as text)."""
    named = any(k in params for k in ("ip", "port", "username", "password"))
    camera = ctx.runtime.peripherals.devices.ptz_camera
    if not named:
        ip, port = camera.address
        return [{"ip": ip, "port": port}]
    return PlainTextResponse(repr(profiles(_camera(ctx, params))))


@ROUTES.get("/system/onvif_camera/stream")
def get_onvif_stream(ctx: Context, params: Params) -> Reply:
    """E-79: the RTSP address of ``channel``."""
    camera = _camera(ctx, params)
    channel = _channel(params)
    ip, _ = camera.address
    user, password = params.text("username"), params.text("password")
    return {"stream": f"rtsp://{user}:{password}@{ip}:554/Streaming/Channels/{channel}01"
                      f"?transportmode=unicast&profile=Profile_{channel}01"}


@ROUTES.get("/system/onvif_camera/move")
def get_onvif_move(ctx: Context, params: Params) -> Reply:
    """E-80: move to an absolute pan/tilt/zoom."""
    camera = _camera(ctx, params)
    pose = PtzPose(params.number("x"), params.number("y"), params.number("zoom"))
    ctx.runtime.peripherals.ptz(lambda now: camera.move_to(now, pose))
    return {"status": OK, "description": "moving to the position"}


@ROUTES.get("/system/onvif_camera/goto_preset")
def get_onvif_goto_preset(ctx: Context, params: Params) -> Reply:
    """E-81."""
    camera = _camera(ctx, params)
    preset = params.text("preset")
    ctx.runtime.peripherals.ptz(lambda now: camera.goto_preset(now, preset))
    return {"status": OK}


@ROUTES.get("/system/onvif_camera/move_speed")
def get_onvif_move_speed(ctx: Context, params: Params) -> Reply:
    """E-82: a continuous move (all zero: stop)."""
    camera = _camera(ctx, params)
    speeds = (params.number("speed_x"), params.number("speed_y"), params.number("speed_zoom"))
    ctx.runtime.peripherals.ptz(lambda now: camera.move_speed(now, *speeds))
    return {"status": "success", "description": "moving at the speed"}


@ROUTES.get("/system/onvif_camera/snapshot")
def get_onvif_snapshot(ctx: Context, params: Params) -> Reply:
    """E-83: ``{"snapshot": <file-system path of the JPEG>}``."""
    _camera(ctx, params)
    _channel(params)
    path = ctx.runtime.peripherals.ptz_snapshot()
    return {"snapshot": fs.vendor_path(ctx, path)}


@ROUTES.get("/system/onvif_camera/temperature")
def get_onvif_temperature(ctx: Context, params: Params) -> Reply:
    """E-84: the thermometry rules' temperatures."""
    _camera(ctx, params)
    env, _ = ctx.runtime.peripherals.environment()
    room = env.temperature
    rules = []
    for rule_id, (spread, point) in enumerate(((0.9, (0.31, 0.89)), (0.3, (0.85, 0.32))),
                                              start=1):
        rules.append({
            "id": rule_id,
            "maxTemperature": round(room + spread / 2, 1),
            "minTemperature": round(room - spread / 2, 1),
            "averageTemperature": round(room, 1),
            "MaxTemperaturePoint": {"positionX": point[0], "positionY": point[1]},
            "MinTemperaturePoint": {"positionX": round(1 - point[0], 3),
                                    "positionY": round(1 - point[1], 3)},
            "isFreezedata": False,
        })
    return {"temperature": {"ThermometryRulesTemperatureInfoList": {
        "ThermometryRulesTemperatureInfo": rules}}}


@ROUTES.get("/system/onvif_camera/pose")
def get_onvif_pose(ctx: Context, params: Params) -> Reply:
    """E-85: pan, tilt and zoom now."""
    camera = _camera(ctx, params)
    pose = ctx.runtime.peripherals.ptz(camera.pose)
    return {"x": float(pose.pan), "y": float(pose.tilt), "zoom": float(pose.zoom)}
