"""The simulated robot as the rest of polynav sees it: the :class:`~polynav.robot.interface.Robot`
protocol over a :class:`~polynav.robot.sim.simulation.Simulation`.

It only forwards: the simulation owns the state. A drive command has no dead-man timeout here
(the runtime adds one); it holds until the next command, clamped to the base's limits.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from typing import TYPE_CHECKING

from polynav.geometry import Twist
from polynav.robot.interface import (
    BatteryState,
    DockSignals,
    ImuReading,
    LaserScan,
    Odometry,
    PersonDetection,
    SignDetection,
)

if TYPE_CHECKING:
    from polynav.robot.sim.simulation import Simulation

log = logging.getLogger(__name__)


class SimRobot:
    """The :class:`~polynav.robot.interface.Robot` face of a simulation."""

    def __init__(self, sim: Simulation) -> None:
        self._sim = sim

    def drive(self, twist: Twist) -> None:
        """Command a body velocity; ignored while the e-stop is pressed."""
        self._sim.drive(twist)

    def read_odometry(self) -> Odometry:
        return self._sim.odometry

    def read_scan(self) -> LaserScan | None:
        """The newest scan, or ``None`` before the first one."""
        return self._sim.scan

    def read_imu(self) -> ImuReading | None:
        return self._sim.imu

    def read_battery(self) -> BatteryState:
        return self._sim.battery

    def estop_pressed(self) -> bool:
        return self._sim.estop

    def read_people(self) -> Sequence[PersonDetection]:
        return self._sim.detect_people()

    def read_signs(self) -> Sequence[SignDetection]:
        """The "no entry" signs the sign camera sees (:class:`~polynav.robot.interface.SignCamera`;
        none for a profile without one)."""
        return self._sim.detect_signs()

    def read_dock(self) -> DockSignals | None:
        return self._sim.dock_signals()

    def dock_contact(self) -> bool:
        """True while the charging contacts touch a charger."""
        return self._sim.docked
