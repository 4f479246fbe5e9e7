"""Watchers: robot states polled every control tick and reported as events when they change.

The backend reports levels (the e-stop button is down, the battery is at 19 %); adapters want
edges (the e-stop was pressed, the battery went low). Each watcher keeps the last level and
returns the event for a change, or nothing; the runtime publishes what they return.
"""

from __future__ import annotations

import logging

from polynav.localization.interface import LocalizationState
from polynav.robot.interface import BatteryState
from polynav.runtime import events

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
