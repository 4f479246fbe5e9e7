"""The simulated battery: a lithium pack that drains with load and charges constant current,
then constant voltage.

Charge is tracked in per cent of capacity. While powered the electronics draw
``battery_idle_drain`` per hour and the wheels ``battery_drain_per_metre`` for each metre they
roll. The pack's open-circuit voltage follows a lithium-ion curve between the empty and full
pack voltages (steep at both ends, flat in the middle), and its terminal voltage sags under load
and rises while charging by the current through ``battery_internal_resistance``. On a charger
the current is ``battery_charge_rate`` (constant current) until the terminal voltage reaches the
full pack voltage; from there the charger holds that voltage and the current falls as the pack
fills (constant voltage), down to a trickle that tops it up to 100 %. Currents follow the
:class:`~polynav.robot.interface.BatteryState` convention: negative while discharging.
"""

from __future__ import annotations

import bisect
import logging

import numpy as np

from polynav.robot.interface import BatteryState
from polynav.robot.sim.config import SimConfig

log = logging.getLogger(__name__)

SECONDS_PER_HOUR = 3600.0

# Open-circuit voltage of a lithium-ion (NMC) pack: state of charge [%] -> share of the span
# from the empty to the full pack voltage.
_SOC = np.array([0.0, 5.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0, 90.0, 100.0])
_SHARE = np.array([0.0, 0.30, 0.40, 0.47, 0.52, 0.56, 0.60, 0.65, 0.71, 0.78, 0.88, 1.0])

#: The least charging current [share of capacity per hour]: the top-up at the end.
TRICKLE_SHARE = 0.03


_SOC_KNOTS: tuple[float, ...] = tuple(_SOC.tolist())
_SHARE_KNOTS: tuple[float, ...] = tuple(_SHARE.tolist())


def open_circuit_voltage(percent: float, empty: float, full: float) -> float:
    """The pack's voltage at rest [V] at ``percent`` charge."""
    return float(empty + (full - empty) * _share(percent))


def _share(percent: float) -> float:
    """``np.interp(percent, _SOC, _SHARE)`` for one float, in plain Python: the same branches
    and the same operations in the same order as NumPy's kernel, so the same bits (checked
    against it by the unit tests), without NumPy's per-call overhead every physics step."""
    xs, ys = _SOC_KNOTS, _SHARE_KNOTS
    if percent < xs[0]:
        return ys[0]
    if percent >= xs[-1]:
        return ys[-1]
    j = bisect.bisect_right(xs, percent) - 1
    if xs[j] == percent:
        return ys[j]
    return (ys[j + 1] - ys[j]) / (xs[j + 1] - xs[j]) * (percent - xs[j]) + ys[j]


class Battery:
    """Charge, voltage and current of the robot's pack."""

    def __init__(self, config: SimConfig, stamp: float = 0.0) -> None:
        self._config = config
        self._percent = config.battery_start_percent
        self._state = self._make_state(stamp, 0.0, charging=False)

    @property
    def state(self) -> BatteryState:
        return self._state

    def charging_current(self) -> float:
        """What the charger drives into the pack now [A]: constant current, then what the
        full voltage allows, never below the trickle; 0 when full."""
        c = self._config
        if self._percent >= 100.0:
            return 0.0
        constant = c.battery_capacity * c.battery_charge_rate / 100.0
        if c.battery_internal_resistance <= 0.0:
            return constant
        rest = open_circuit_voltage(self._percent, c.battery_empty_voltage,
                                    c.battery_full_voltage)
        held = (c.battery_full_voltage - rest) / c.battery_internal_resistance
        return min(constant, max(held, TRICKLE_SHARE * c.battery_capacity))

    def update(self, dt: float, travel: float, *, charging: bool, stamp: float) -> None:
        """Advance ``dt`` [s] in which the wheels rolled ``travel`` [m], on a charger or not."""
        c = self._config
        if charging:
            current = self.charging_current()
        else:
            moving = c.battery_drain_per_metre * travel / dt * SECONDS_PER_HOUR
            current = -c.battery_capacity * (c.battery_idle_drain + moving) / 100.0
        before = self._percent
        gained = 100.0 * current / c.battery_capacity * dt / SECONDS_PER_HOUR
        self._percent = min(100.0, max(0.0, before + gained))
        if self._percent == 0.0 and before > 0.0:
            log.warning("simulated battery is empty")
        self._state = self._make_state(stamp, current, charging=charging)

    def _make_state(self, stamp: float, current: float, *, charging: bool) -> BatteryState:
        c = self._config
        rest = open_circuit_voltage(self._percent, c.battery_empty_voltage,
                                    c.battery_full_voltage)
        voltage = rest + current * c.battery_internal_resistance
        if charging:
            voltage = min(voltage, c.battery_full_voltage)
        return BatteryState(
            stamp=stamp,
            percent=self._percent,
            voltage=max(0.0, voltage),
            current=current,
            charging=charging,
            charger_voltage=c.battery_full_voltage if charging else 0.0,
            electronics_current=c.battery_capacity * c.battery_idle_drain / 100.0,
        )
