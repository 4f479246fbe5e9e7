"""Auto-charge: a runtime policy on the task engine.

Below ``low_battery_percent`` (with the ``auto_charge`` setting on, navigating on a map) the
robot takes a detour as soon as it is at a safe point: the running task, if any, is paused, the
robot docks onto the nearest charger of its map, charges to
``full_battery_percent`` and the task goes on where it was (a navigation leg is driven again
from the charger). If docking or charging fails the waiting task is cancelled: a robot that
cannot charge should stop and say so, not drain its battery flat on its round.

A safe point: no goal across maps (a lift ride is never interrupted), no docking or leaving a
charger under way, no local move. The policy fires once per discharge: it re-arms when the
battery is back above the low threshold.
"""

from __future__ import annotations

import logging
from typing import TYPE_CHECKING

from polynav.runtime import events
from polynav.site import PointKind
from polynav.tasks.actions.charging import BatteryWaitAction
from polynav.tasks.actions.navigation import ChargeAction
from polynav.tasks.control import Sequence
from polynav.tasks.engine import Task

if TYPE_CHECKING:
    from polynav.runtime.robot_runtime import RobotRuntime

log = logging.getLogger(__name__)

AUTO_CHARGE = "auto_charge"  # the detour task's kind
CHARGE_TIMEOUT = 6 * 3600.0  # [s] on the charger before giving up


class AutoCharge:
    """Watches the battery each control tick and sends the robot to charge."""

    def __init__(self, runtime: RobotRuntime) -> None:
        self._runtime = runtime
        self._armed = True
        self._no_charger_said = False
        runtime.tasks.engine.when_ended(self._ended)

    def tick(self, now: float) -> None:
        rt = self._runtime
        settings = rt.settings()
        battery = rt.robot.read_battery()
        if battery.percent >= settings.low_battery_percent:
            self._armed = True
            return
        if not (self._armed and settings.auto_charge and not battery.charging):
            return
        if not self._safe():
            return
        charger = self._charger()
        if charger is None:
            if not self._no_charger_said:
                log.warning("battery low (%.1f %%) and no charger point on map %s: "
                            "auto-charge cannot dock", battery.percent, rt.map_name)
                self._no_charger_said = True
            return
        self._armed = False
        engine = rt.tasks.engine
        waiting = engine.running
        tree = Sequence([ChargeAction({"point": charger}, name="dock"),
                         BatteryWaitAction({"percent": settings.full_battery_percent,
                                            "timeout": CHARGE_TIMEOUT}, name="charge")],
                        name="auto-charge")
        task = Task("auto-charge", tree, owner="runtime", kind=AUTO_CHARGE, temporary=True)
        log.warning("battery low (%.1f %%): auto-charge at %s%s", battery.percent, charger,
                    f", task {waiting.name!r} waits" if waiting is not None else "")
        rt.publish(events.AutoChargeStarted(now, float(battery.percent), charger,
                                            None if waiting is None else waiting.id))
        engine.interrupt(task)

    def _safe(self) -> bool:
        rt = self._runtime
        snap = rt.status()
        if snap.mode != "navigating" or rt.map_name is None or snap.route is not None:
            return False
        if rt.local_move_active or rt.tasks.engine.suspended is not None:
            return False
        return snap.phase not in ("dock", "leave_charger")

    def _charger(self) -> str | None:
        rt = self._runtime
        if rt.map_name is None:
            return None
        chargers = [p for p in rt.store.points(map_name=rt.map_name) if p.kind is PointKind.CHARGER]
        if not chargers:
            return None
        here = rt.status().pose
        return min(chargers, key=lambda p: (p.pose.x - here.x) ** 2 + (p.pose.y - here.y) ** 2
                   ).name

    def _ended(self, task: Task) -> None:
        if task.kind != AUTO_CHARGE:
            return
        rt = self._runtime
        percent = float(rt.robot.read_battery().percent)
        charged = task.state.value == "COMPLETE"
        reason = "" if charged else (task.note or _first_result(task) or task.state.value)
        log.info("auto-charge %s at %.1f %%%s", "done" if charged else "failed", percent,
                 f": {reason}" if reason else "")
        rt.publish(events.AutoChargeEnded(rt.now(), charged, percent, reason))
        rt.tasks.engine.delete(task.id)


def _first_result(task: Task) -> str:
    return next((n.result for n in task.root.walk() if n.result), "")
