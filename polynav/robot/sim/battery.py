"""The simulated battery: charge drains with time and wheel travel, and refills on a charger.

Charge is tracked in per cent of capacity. While powered the robot loses ``battery_idle_drain``
per hour, plus ``battery_drain_per_metre`` for each metre its wheels roll; on a charger it gains
``battery_charge_rate`` per hour instead (the charger also feeds the electronics) until full.
Voltage is linear in charge between the empty and full pack voltages, and the current follows
from the rate of change: ``capacity [Ah] * rate [%/h] / 100``, negative while discharging (the
:class:`~polynav.robot.interface.BatteryState` convention). The charger holds the pack's full
voltage; the electronics draw the idle drain's current.
"""

from __future__ import annotations

import logging

from polynav.robot.interface import BatteryState
from polynav.robot.sim.config import SimConfig

log = logging.getLogger(__name__)

SECONDS_PER_HOUR = 3600.0


class Battery:
    """Charge, voltage and current of the robot's pack."""

    def __init__(self, config: SimConfig, stamp: float = 0.0) -> None:
        self._config = config
        self._percent = config.battery_start_percent
        self._state = self._make_state(stamp, 0.0, charging=False)

    @property
    def state(self) -> BatteryState:
        return self._state

    def update(self, dt: float, travel: float, *, charging: bool, stamp: float) -> None:
        """Advance ``dt`` [s] in which the wheels rolled ``travel`` [m], on a charger or not."""
        c = self._config
        if charging:
            rate = c.battery_charge_rate if self._percent < 100.0 else 0.0
        else:
            moving = c.battery_drain_per_metre * travel / dt * SECONDS_PER_HOUR
            rate = -(c.battery_idle_drain + moving)
        before = self._percent
        self._percent = min(100.0, max(0.0, before + rate * dt / SECONDS_PER_HOUR))
        if self._percent == 0.0 and before > 0.0:
            log.warning("simulated battery is empty")
        self._state = self._make_state(stamp, rate, charging=charging)

    def _make_state(self, stamp: float, rate: float, *, charging: bool) -> BatteryState:
        c = self._config
        voltage = c.battery_empty_voltage + (
            c.battery_full_voltage - c.battery_empty_voltage
        ) * self._percent / 100.0
        return BatteryState(
            stamp=stamp,
            percent=self._percent,
            voltage=voltage,
            current=c.battery_capacity * rate / 100.0,
            charging=charging,
            charger_voltage=c.battery_full_voltage if charging else 0.0,
            electronics_current=c.battery_capacity * c.battery_idle_drain / 100.0,
        )
