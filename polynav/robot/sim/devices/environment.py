"""Simulated environment and air sensors: readings that drift on the clock.

Each quantity is an Ornstein-Uhlenbeck process around its mean (it wanders, and is pulled back
with time constant ``tau``), advanced in fixed steps of ``STEP`` seconds of the runtime's clock
with a seeded generator, so a reading at a given time is the same for a seed however often the
sensors are read. Particulates keep their physical order (PM1.0 <= PM2.5 <= PM10) and nothing
goes below zero. The two sensor boxes share the room they measure: the air box reads the same
temperature and humidity as the environment box, plus its own small offset.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from polynav.robot.devices import AirReading, EnvReading

STEP = 1.0  # [s] of the runtime's clock between drift updates


@dataclass(frozen=True, slots=True)
class Drift:
    """One drifting quantity: mean, stationary spread (standard deviation) and time constant
    [s]."""

    mean: float
    spread: float
    tau: float


# An office floor on a working day.
QUANTITIES: dict[str, Drift] = {
    "temperature": Drift(24.0, 0.8, 600.0),
    "humidity": Drift(45.0, 4.0, 900.0),
    "smoke": Drift(0.5, 0.3, 120.0),
    "pm1_0": Drift(8.0, 2.0, 300.0),
    "pm2_5": Drift(14.0, 3.0, 300.0),
    "pm10": Drift(25.0, 5.0, 300.0),
    "lel": Drift(0.2, 0.1, 300.0),
    "noise": Drift(45.0, 4.0, 20.0),
    "co2": Drift(650.0, 60.0, 600.0),
    "illuminance": Drift(420.0, 40.0, 120.0),
}


class SimEnvironmentSensors:
    """Implements :class:`~polynav.robot.devices.EnvironmentSensors`."""

    def __init__(self, seed: int = 0, now: float = 0.0) -> None:
        self._rng = np.random.default_rng(np.random.SeedSequence([seed, 0x5E45]))
        self._t = now
        # Start each quantity at a draw from its stationary spread.
        self._values = {
            name: q.mean + q.spread * float(self._rng.standard_normal())
            for name, q in QUANTITIES.items()
        }
        self._offsets = (0.3 * float(self._rng.standard_normal()),
                         1.5 * float(self._rng.standard_normal()))

    def read_env(self, now: float) -> EnvReading:
        v = self._at(now)
        pm1, pm25, pm10 = sorted((v["pm1_0"], v["pm2_5"], v["pm10"]))
        return EnvReading(
            stamp=self._t, temperature=round(v["temperature"], 2),
            humidity=round(v["humidity"], 2), smoke=round(v["smoke"], 3),
            pm1_0=round(pm1, 2), pm2_5=round(pm25, 2), pm10=round(pm10, 2),
            lel=round(v["lel"], 3), noise=round(v["noise"], 1),
        )

    def read_air(self, now: float) -> AirReading:
        v = self._at(now)
        dt, drh = self._offsets
        return AirReading(
            stamp=self._t, temperature=round(v["temperature"] + dt, 2),
            humidity=round(min(100.0, v["humidity"] + drh), 2), co2=round(v["co2"], 1),
            illuminance=round(v["illuminance"], 1),
        )

    def _at(self, now: float) -> dict[str, float]:
        steps = int(math.floor((now - self._t) / STEP + 1e-9))
        for _ in range(max(0, steps)):
            for name, q in QUANTITIES.items():
                decay = math.exp(-STEP / q.tau)
                noise = q.spread * math.sqrt(1.0 - decay * decay)
                value = q.mean + (self._values[name] - q.mean) * decay
                value += noise * float(self._rng.standard_normal())
                self._values[name] = max(0.0, value)
            self._t += STEP
        return self._values
