"""``/api/robot/...``: the status, clearing errors, pause/resume and charging (issue 33 item 2,
calls real Puwei clients make that the exported document lacks; docs/puwei.md).

* ``status``: the O_STATUS fields (:mod:`polynav.protocols.puwei.status`), ``state`` and
  ``err`` from the tables in docs/puwei.md.
* ``clear``: releases the software e-stop and acknowledges the last navigation failure (its
  ``4-x`` error is no longer reported). A pressed e-stop button or lost localization stay:
  they clear when their cause does.
* ``pause?value=true|false``: pauses (default) or resumes the running task, else the goal.
* ``charge?value=true|false``: docks onto the map's charger (a ``charge_action`` task, the
  same docking as everywhere, DESIGN §2), or cancels docking/charging.
"""

from __future__ import annotations

import datetime as dt
import logging
from dataclasses import dataclass
from typing import Any

from polynav.errors import Conflict, NotFound
from polynav.protocols.puwei import status as codes
from polynav.protocols.puwei.context import Context
from polynav.protocols.puwei.endpoint import RouteList
from polynav.protocols.puwei.request import PuweiRequest
from polynav.runtime.status import StatusSnapshot
from polynav.site import PointKind

log = logging.getLogger(__name__)

ROUTES = RouteList()

#: The kind of the charge task (so that ``charge?value=false`` cancels only that).
CHARGE_KIND = "puwei_charge"


@dataclass
class Cleared:
    """The failed attempt a client acknowledged with ``clear``."""

    attempt_id: int | None = None


def cleared(ctx: Context) -> Cleared:
    return ctx.state("puwei.cleared", Cleared)


def charger_point(ctx: Context) -> str | None:
    """The charger point of the map navigation runs on, if it has one (the first by name)."""
    map_name = ctx.runtime.status().map
    if map_name is None:
        return None
    chargers = sorted(p.name for p in ctx.runtime.store.points(map_name=map_name)
                      if p.kind is PointKind.CHARGER)
    return chargers[0] if chargers else None


def robot_status(ctx: Context, snap: StatusSnapshot | None = None) -> dict[str, Any]:
    """The status body (also what O_STATUS carries), of ``snap`` (default: the latest)."""
    rt = ctx.runtime
    if snap is None:
        snap = rt.status()
    task = rt.tasks.running()
    task_state = None if task is None else task["state"]
    err = codes.err_codes(snap, low_battery_percent=rt.settings().low_battery_percent,
                          cleared_attempt=cleared(ctx).attempt_id)
    state = codes.state_of(snap, task_running=task_state == "WORKING",
                           task_paused=task_state == "PAUSED")
    battery = rt.robot.read_battery()
    stamp = rt.calendar_epoch + dt.timedelta(seconds=snap.stamp)
    body = codes.status_body(snap, state=state, err=err, voltage=battery.voltage,
                             current=battery.current, time_stamp_ms=int(stamp.timestamp() * 1000))
    body["map"] = snap.map
    return body


@ROUTES.get("/api/robot/status", inline=True)
def status(ctx: Context, request: PuweiRequest) -> dict[str, Any]:
    return robot_status(ctx)


def clear_errors(ctx: Context) -> list[str]:
    """Release the software e-stop and acknowledge the last failure; the errors left (HTTP
    ``robot/clear``, WebSocket I_CLEAR)."""
    rt = ctx.runtime
    snap = rt.status()
    if snap.estop_software:
        rt.set_software_estop(False)
    if snap.navigation_state == "failed":
        cleared(ctx).attempt_id = snap.attempt_id
    return list(robot_status(ctx)["err"])


def set_paused(ctx: Context, on: bool) -> None:
    """Pause (``on``) or resume the running task, else the goal (HTTP ``robot/pause``,
    WebSocket I_PAUSE)."""
    rt = ctx.runtime
    task = rt.tasks.running()
    if task is not None:
        if on:
            rt.tasks.pause(task["id"])
        else:
            rt.tasks.resume(task["id"])
        return
    if on:
        rt.pause()
    else:
        rt.resume()


def set_charging(ctx: Context, on: bool) -> None:
    """Dock onto the charger (``on``) or stop docking/charging (HTTP ``robot/charge``,
    WebSocket I_CHARGE)."""
    rt = ctx.runtime
    if not on:
        task = rt.tasks.running()
        if task is None or task["kind"] != CHARGE_KIND:
            raise Conflict("no charging under way")
        rt.tasks.cancel(task["id"])
        return
    if rt.status().mode != "navigating":
        raise Conflict("charging needs navigation (GET /api/roslaunch/navigation/:name)")
    point = charger_point(ctx)
    if point is None:
        raise NotFound("charger point on map", str(rt.status().map))
    rt.tasks.create({"type": "charge_action", "name": "charge", "point": point},
                    name="charge", owner="puwei", kind=CHARGE_KIND, temporary=True, start=True)
    log.info("puwei: docking onto %s", point)


@ROUTES.get("/api/robot/clear")
def clear(ctx: Context, request: PuweiRequest) -> list[str]:
    """``data``: the errors still reported after clearing."""
    return clear_errors(ctx)


@ROUTES.get("/api/robot/pause")
def pause(ctx: Context, request: PuweiRequest) -> None:
    """Pause (``value`` true, the default) or resume the running task, else the goal."""
    set_paused(ctx, request.flag("value", True))


@ROUTES.get("/api/robot/charge")
def charge(ctx: Context, request: PuweiRequest) -> None:
    """Dock onto the charger (``value`` true, the default) or stop docking/charging."""
    set_charging(ctx, request.flag("value", True))
