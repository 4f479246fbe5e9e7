"""Yunji commands about the robot as a device: Wi-Fi, LED strip, self-diagnosis, power,
software version/update/restart and shutdown (§3.13, §3.15-§3.19).

The device itself is :class:`polynav.runtime.device.Device` (``runtime.device``); this module
converts parameters and results. Decisions where the spec is silent are in ``docs/yunji.md``.
"""

from __future__ import annotations

import time

from polynav.errors import InvalidRequest
from polynav.protocols.yunji.context import (
    Context,
    Handler,
    Params,
    optional_int,
    parse_float,
    required,
)
from polynav.protocols.yunji.messages import Reply, Status

MAX_DELAY_MINUTES = 14400  # §3.15
NO_UPDATE_SOURCE = "no update source: polynav is updated with pip by its owner"


def _percent(params: Params, name: str) -> float:
    value = parse_float(name, required(params, name))
    if not 0.0 <= value <= 100.0:
        raise InvalidRequest(name, f"must be within [0, 100], got {value:g}")
    return value


# -- Wi-Fi (§3.13) ---------------------------------------------------------------------------


def wifi_list(ctx: Context, params: Params) -> Reply:
    """§3.13.1: SSID -> signal strength (0-100, §A-P11)."""
    return Reply(results={n.ssid: n.signal for n in ctx.runtime.device.network().visible})


def wifi_connect(ctx: Context, params: Params) -> Reply:
    """§3.13.2: join a network in range; the password may be left out for one joined before.
    Out of range, a missing or a wrong password: ``INVALID_REQUEST`` (§A-P11)."""
    ctx.runtime.device.join_network(required(params, "SSID"), params.get("password"))
    return Reply()


def wifi_get_active_connection(ctx: Context, params: Params) -> Reply:
    """§3.13.3: the joined network's SSID, ``""`` when none."""
    return Reply(results=ctx.runtime.device.network().active or "")


def wifi_info(ctx: Context, params: Params) -> Reply:
    """§3.13.4: the address from the joined network (``""`` when none) and the card's MAC."""
    network = ctx.runtime.device.network()
    return Reply(results={"IPaddr": network.ip_address, "HWaddr": network.mac})


def wifi_detail_list(ctx: Context, params: Params) -> Reply:
    """§3.13.5: per network SSID, SIGNAL, ACTIVE (JSON bool), FREQ ("2462 MHz"), SECURITY."""
    network = ctx.runtime.device.network()
    return Reply(results={
        n.ssid: {
            "SSID": n.ssid,
            "SIGNAL": n.signal,
            "ACTIVE": n.ssid == network.active,
            "FREQ": f"{n.frequency} MHz",
            "SECURITY": n.security,
        }
        for n in network.visible
    })


# -- LED strip (§3.17) -----------------------------------------------------------------------


def led_set_luminance(ctx: Context, params: Params) -> Reply:
    """§3.17.1: brightness 0-100, kept across restarts."""
    ctx.runtime.device.set_light(luminance=_percent(params, "value"))
    return Reply()


def led_set_color(ctx: Context, params: Params) -> Reply:
    """§3.17.2: r, g, b 0-100, kept across restarts; all 0 "cannot take effect" (§A-P10):
    ``UNKNOWN_ERROR``, the strip unchanged."""
    colour = (_percent(params, "r"), _percent(params, "g"), _percent(params, "b"))
    if colour == (0.0, 0.0, 0.0):
        return Reply(Status.UNKNOWN_ERROR, "r, g and b are all 0: the colour was not changed")
    ctx.runtime.device.set_light(colour=colour)
    return Reply()


# -- diagnosis, power (§3.18, §3.19) ---------------------------------------------------------


def diagnosis_get_result(ctx: Context, params: Params) -> Reply:
    """§3.18: each part's latest check; ``time_stamp`` in Unix seconds (§A-P13)."""
    results = ctx.runtime.device.self_check.results
    if not results:
        return Reply(Status.UNKNOWN_ERROR, "no self-diagnosis has run yet")
    offset = time.time() - ctx.runtime.now()  # the runtime's clock to the Unix epoch
    return Reply(results={
        part: {
            "status": check.ok,
            "time_stamp": round(check.stamp + offset, 6),
            "total_count": check.total,
            "success_count": check.passed,
        }
        for part, check in results.items()
    })


def get_power_status(ctx: Context, params: Params) -> Reply:
    """§3.19: battery [%], current [A] (+ charging), voltages [V] (§A-P8)."""
    battery = ctx.runtime.device.battery()
    return Reply(results={
        "battery_capacity": int(round(battery.percent)),
        "battery_current": round(battery.current, 3),
        "battery_voltage": round(battery.voltage, 3),
        "charge_voltage": round(battery.charger_voltage, 3),
        "charger_connected_notice": battery.charging,
        "head_current": round(battery.electronics_current, 3),
    })


# -- software and power cycle (§3.15, §3.16) -------------------------------------------------


def software_check_for_update(ctx: Context, params: Params) -> Reply:
    """§3.16.2: polynav never contacts a server by itself: the installed version is the
    latest it knows of, and there is nothing to update to."""
    return Reply(results={
        "version_latest": ctx.version,
        "version_current": ctx.version,
        "enable_update": False,
    })


def software_update(ctx: Context, params: Params) -> Reply:
    """§3.16.3: the spec's failure form: nothing newer to install from here."""
    return Reply(Status.UNKNOWN_ERROR, NO_UPDATE_SOURCE)


def software_restart(ctx: Context, params: Params) -> Reply:
    """§3.16.4: 02006 first, navigation reloaded, the soft e-stop off; the reply follows."""
    ctx.runtime.device.power.restart_software()
    return Reply()


def shutdown(ctx: Context, params: Params) -> Reply:
    """§3.15: 02000 now, power off 10 s later; ``reboot=true`` powers on 5 s later, or
    ``delay`` minutes (0..14400) later (§A-P7). The notice may arrive before the reply."""
    reboot = params.get("reboot", "false")
    if reboot not in ("true", "false"):
        raise InvalidRequest("reboot", f"must be true or false, got {reboot!r}")
    delay = optional_int(params, "delay", 0)
    assert delay is not None
    if not 0 <= delay <= MAX_DELAY_MINUTES:
        raise InvalidRequest("delay", f"must be within [0, {MAX_DELAY_MINUTES}] minutes, "
                                      f"got {delay}")
    ctx.runtime.device.power.shutdown(reboot=reboot == "true", delay=60.0 * delay)
    return Reply()


HANDLERS: dict[str, Handler] = {
    "/api/wifi/list": wifi_list,
    "/api/wifi/connect": wifi_connect,
    "/api/wifi/get_active_connection": wifi_get_active_connection,
    "/api/wifi/info": wifi_info,
    "/api/wifi/detail_list": wifi_detail_list,
    "/api/LED/set_luminance": led_set_luminance,
    "/api/LED/set_color": led_set_color,
    "/api/diagnosis/get_result": diagnosis_get_result,
    "/api/get_power_status": get_power_status,
    "/api/software/check_for_update": software_check_for_update,
    "/api/software/update": software_update,
    "/api/software/restart": software_restart,
    "/api/shutdown": shutdown,
}
