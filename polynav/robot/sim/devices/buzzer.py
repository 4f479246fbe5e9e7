"""The simulated chassis buzzer: on or off, and since when (for a log of who sounded it)."""

from __future__ import annotations


class SimBuzzer:
    """Implements :class:`~polynav.robot.devices.Buzzer`."""

    def __init__(self) -> None:
        self._on = False
        self.since: float | None = None  # when it last changed [s]

    @property
    def on(self) -> bool:
        return self._on

    def set(self, now: float, on: bool) -> None:
        if on != self._on:
            self._on = on
            self.since = now
