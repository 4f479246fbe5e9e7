"""Network and follow-mode endpoints (galileo-http-a §3.11, §3.13: E-50, E-53, E-54, E-57,
E-70, E-71, E-74).

Wi-Fi is the simulated wireless card (:mod:`polynav.robot.sim.wifi`): ``/system/wifi`` joins a
network in range with its password, and the robot counts as online while it is joined to a
network in range (the simulator has no internet beyond its access points; nothing is sent).
A failed join answers ``status`` with the reason and HTTP 400, and leaves the connection as it
was. ``restart_router`` checks its parameters and that the robot is on a network, and answers
``ok``: the simulated site has no router to log in to, so nothing is restarted. The follow
modes (visual tracking, UWB) are switches polynav keeps; it has no follow behaviour, so
switching them on does not move the robot.
"""

from __future__ import annotations

import ipaddress

from polynav.errors import Conflict, InvalidRequest
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.endpoint import Reply, RouteList
from polynav.protocols.galileo.params import Params
from polynav.protocols.galileo.system_replies import OK, string_reply

ROUTES = RouteList()

ROUTER_TYPES = ("oray", "tplink", "huawei", "tcl")


@ROUTES.get("/system/wifi")
def get_wifi(ctx: Context, params: Params) -> Reply:
    """E-50: join ``ssid`` with ``password``."""
    ssid = params.text("ssid")
    password = params.text("password")
    device = ctx.runtime.device

    def join() -> None:
        device.join_network(ssid, password or None)
        if device.network().active != ssid:
            raise Conflict(f"joined {ssid!r} but it is not reachable from here")

    return string_reply("status", join)


@ROUTES.get("/system/is_online")
def get_is_online(ctx: Context, params: Params) -> Reply:
    """E-57: ``{"result": <joined to a network in range>}``."""
    return {"result": ctx.runtime.device.network().active is not None}


@ROUTES.get("/system/restart_router")
def get_restart_router(ctx: Context, params: Params) -> Reply:
    """E-74: see the module docstring."""
    kind = params.text("type", "oray")
    if kind not in ROUTER_TYPES:
        raise InvalidRequest("type", f"must be one of {', '.join(ROUTER_TYPES)}, got {kind!r}")
    address = params.text("ip")
    try:
        ipaddress.ip_address(address)
    except ValueError:
        raise InvalidRequest("ip", f"is not an IP address: {address!r}") from None
    params.text("username")
    params.text("password")
    if ctx.runtime.device.network().active is None:
        raise Conflict("the robot is not on a network: no router to reach")
    return {"status": OK}


def _flags(ctx: Context) -> dict[str, bool]:
    return ctx.state("galileo.follow_modes", lambda: {"tracking": False, "uwb": False})


@ROUTES.get("/system/tracking_mode", inline=True)
def get_tracking_mode(ctx: Context, params: Params) -> Reply:
    """E-53."""
    return {"tracking_flag": _flags(ctx)["tracking"]}


@ROUTES.put("/system/tracking_mode")
def put_tracking_mode(ctx: Context, params: Params) -> Reply:
    """E-54: ``{"tracking_flag": <bool>}`` (A-29)."""
    _flags(ctx)["tracking"] = params.boolean("enable")
    return {"tracking_flag": _flags(ctx)["tracking"]}


@ROUTES.get("/system/uwb_track", inline=True)
def get_uwb_track(ctx: Context, params: Params) -> Reply:
    """E-70."""
    return {"enable": _flags(ctx)["uwb"]}


@ROUTES.put("/system/uwb_track")
def put_uwb_track(ctx: Context, params: Params) -> Reply:
    """E-71."""
    _flags(ctx)["uwb"] = params.boolean("enable")
    return {"status": OK}
