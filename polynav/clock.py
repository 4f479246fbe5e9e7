"""Clocks: the one source of "now" for every service.

Services never read the wall clock (STYLE R8); they are handed ``now`` or a :class:`Clock`. In the
simulator a :class:`ManualClock` is advanced by the simulation loop, so a whole mission runs in
seconds of wall time and repeats exactly for a seed.
"""

from __future__ import annotations

import time
from typing import Protocol


class Clock(Protocol):
    """A monotonic time source in seconds."""

    def now(self) -> float: ...


class WallClock:
    """Real monotonic time, for a robot on real hardware."""

    def now(self) -> float:
        return time.monotonic()


class ManualClock:
    """Time that moves only when told to: simulated time and tests."""

    def __init__(self, start: float = 0.0) -> None:
        self._now = float(start)

    def now(self) -> float:
        return self._now

    def advance(self, dt: float) -> float:
        """Move time forward by ``dt`` [s] and return the new time."""
        if dt < 0.0:
            raise ValueError("a clock never runs backwards")
        self._now += dt
        return self._now

    def set(self, t: float) -> None:
        if t < self._now:
            raise ValueError("a clock never runs backwards")
        self._now = float(t)
