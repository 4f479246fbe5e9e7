"""The robot as a device: what a robot's owner manages besides navigation (network, lights,
self-diagnosis, power and software life cycle).

:class:`Device` is a runtime service: the runtime builds it and ticks it every control period.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from polynav.runtime.robot_runtime import RobotRuntime


class Device:
    """The device services of one robot."""

    def __init__(self, runtime: RobotRuntime) -> None:
        self._runtime = runtime

    def tick(self, now: float) -> None:
        """One control period (called by the runtime's loop, between commands)."""
