"""Watchers: robot states polled every control tick and reported as events when they change.

The backend reports levels (the e-stop button is down, the battery is at 19 %); adapters want
edges (the e-stop was pressed, the battery went low). Each watcher keeps the last level and
returns the event for a change, or nothing; the runtime publishes what they return.
"""

from __future__ import annotations

import logging
import math

from polynav.geometry import Twist, angle_diff
from polynav.localization.interface import LocalizationState
from polynav.robot.interface import BatteryState, LaserScan, Odometry
from polynav.runtime import events
from polynav.runtime.self_check import blocked_sector

log = logging.getLogger(__name__)

# Low-battery hysteresis [%]: the event fires again only after the charge rose this far above.
BATTERY_HYSTERESIS = 1.0


class EStopWatcher:
    """The hardware button and the software e-stop, reported together on any change."""

    def __init__(self, hardware: bool) -> None:
        self.hardware = hardware
        self.software = False

    @property
    def active(self) -> bool:
        return self.hardware or self.software

    def update(self, now: float, hardware: bool, software: bool) -> events.EStopChanged | None:
        """The event for a change of either e-stop since the last update, else ``None``."""
        if (hardware, software) == (self.hardware, self.software):
            return None
        self.hardware, self.software = hardware, software
        log.info("e-stop: hardware %s, software %s", hardware, software)
        return events.EStopChanged(now, hardware, software, hardware or software)


class LocalizationWatcher:
    """The localization state; its quality rides along but a change of quality alone is quiet
    (it moves every tick)."""

    def __init__(self) -> None:
        self.state = LocalizationState.UNINITIALIZED.value

    def update(
        self, now: float, state: str, quality: float
    ) -> events.LocalizationChanged | None:
        """The event for a change of state since the last update, else ``None``."""
        if state == self.state:
            return None
        self.state = state
        log.info("localization %s (quality %.2f)", state, quality)
        return events.LocalizationChanged(now, state, float(quality))


class BatteryWatcher:
    """Charging started or stopped, and the charge falling below the low-battery threshold.

    The low-battery event fires once per discharge: again only after the charge rose
    :data:`BATTERY_HYSTERESIS` above the threshold, so that noise around it does not repeat it.
    """

    def __init__(self, battery: BatteryState, low_percent: float) -> None:
        self.charging = battery.charging
        self.low = battery.percent < low_percent

    def update(
        self, now: float, battery: BatteryState, low_percent: float
    ) -> list[events.RuntimeEvent]:
        """The events for what changed since the last update, in publishing order."""
        out: list[events.RuntimeEvent] = []
        if battery.charging != self.charging:
            self.charging = battery.charging
            log.info("charging %s at %.1f %%", "started" if battery.charging else "stopped",
                     battery.percent)
            out.append(events.ChargeChanged(now, battery.charging))
        if not self.low and battery.percent < low_percent:
            self.low = True
            log.warning("battery low: %.1f %%", battery.percent)
            out.append(events.LowBattery(now, float(battery.percent)))
        elif self.low and battery.percent >= low_percent + BATTERY_HYSTERESIS:
            self.low = False
        return out


DISPLACED_DISTANCE = 0.3  # [m] moved with no drive command: someone pushed or carried it
DISPLACED_ROTATION = 0.5  # [rad]
STILL_SPEED = 0.01  # [m/s], [rad/s]


class DisplacementWatcher:
    """The robot moving while nothing drives it: wheel odometry adds up motion over ticks in
    which the commanded velocity is zero (braking from a command counts too, but stays well
    under the thresholds). Reported once per push; re-armed when the robot stands still."""

    def __init__(self) -> None:
        self._last: Odometry | None = None
        self._distance = 0.0
        self._rotation = 0.0
        self._reported = False

    def update(
        self, now: float, odometry: Odometry, commanded: Twist
    ) -> events.RuntimeEvent | None:
        last, self._last = self._last, odometry
        if commanded.linear != 0.0 or commanded.angular != 0.0 or last is None:
            self._distance = self._rotation = 0.0
            self._reported = False
            return None
        self._distance += odometry.pose.distance_to(last.pose)
        self._rotation += abs(angle_diff(odometry.pose.theta, last.pose.theta))
        still = (
            abs(odometry.twist.linear) < STILL_SPEED and abs(odometry.twist.angular) < STILL_SPEED
        )
        if not self._reported and (
            self._distance >= DISPLACED_DISTANCE or self._rotation >= DISPLACED_ROTATION
        ):
            self._reported = True
            log.warning("moved %.2f m / %.2f rad without a drive command", self._distance,
                        self._rotation)
            return events.RobotDisplaced(now, self._distance)
        if still and self._reported:
            self._distance = self._rotation = 0.0
            self._reported = False
        return None


class ForeignObjectWatcher:
    """Something inside the robot's housing (in the lidar's slot): reported once when a scan
    first shows it over more than ``min_sector`` of the view, re-armed when it is gone."""

    def __init__(self, min_sector: float) -> None:
        self._min_sector = min_sector
        self._present = False
        self._last_stamp: float | None = None

    def update(self, now: float, scan: LaserScan | None) -> events.RuntimeEvent | None:
        if scan is None or scan.stamp == self._last_stamp:
            return None
        self._last_stamp = scan.stamp
        sector = blocked_sector(scan)
        present = sector >= self._min_sector
        changed, self._present = present != self._present, present
        if present and changed:
            log.warning("an object blocks %.0f deg of the lidar's view from inside",
                        math.degrees(sector))
            return events.ForeignObjectDetected(now, sector)
        return None
