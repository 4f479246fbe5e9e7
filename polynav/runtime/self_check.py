"""The robot's self-diagnosis: periodic checks of its parts from what their readings show.

Every ``period`` seconds of the runtime's clock (the first time ``BOOT`` seconds after the
first tick) each part is checked: a part passes when its
readings are fresh and plausible (the lidar: a scan within a second, with returns, and nothing
stuck inside the housing; the IMU and the wheel odometry, the motor boards and their bus: a
reading within a second; the power board: a battery voltage; the sensor board: lidar and IMU
both; the radio board: the wireless card answers). Each part keeps its latest result, when it
was checked, and how many checks it had and passed.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from polynav.robot.interface import LaserScan, Robot

FRESH = 1.0  # [s] the newest reading may be this old
PERIOD = 10.0  # [s] between checks
BOOT = 2.0  # [s] from the first tick to the first check (the sensors start up)
HOUSING_RADIUS = 0.15  # [m] returns nearer than this come from inside the robot
PARTS = (
    "sensor_core", "motor_core_right", "motor_core_left", "radio_core", "power_core", "laser",
    "IMU", "CAN",
)


@dataclass(frozen=True, slots=True)
class PartCheck:
    ok: bool
    stamp: float
    total: int
    passed: int


def blocked_sector(scan: LaserScan) -> float:
    """The angle [rad] of the lidar's view that returns from inside the housing."""
    ranges = scan.ranges
    inside = np.isfinite(ranges) & (ranges < HOUSING_RADIUS)
    return float(np.count_nonzero(inside)) * abs(scan.angle_increment)


class SelfCheck:
    """Checks ``robot``'s parts every ``period`` seconds; ``results`` has the latest."""

    def __init__(self, robot: Robot, radio_ok: bool, period: float = PERIOD) -> None:
        self._robot = robot
        self._radio_ok = radio_ok
        self._period = period
        self._due: float | None = None
        self.results: dict[str, PartCheck] = {}

    def tick(self, now: float) -> None:
        if self._due is None:
            self._due = now + BOOT
        if now < self._due - 1e-9:
            return
        self._due = now + self._period
        for part, ok in self._check(now).items():
            last = self.results.get(part, PartCheck(False, now, 0, 0))
            self.results[part] = replace(
                last, ok=ok, stamp=now, total=last.total + 1, passed=last.passed + int(ok)
            )

    def _check(self, now: float) -> dict[str, bool]:
        robot = self._robot
        scan = robot.read_scan()
        laser = bool(
            scan is not None
            and now - scan.stamp <= FRESH
            and np.any(np.isfinite(scan.ranges))
            and blocked_sector(scan) < np.radians(5.0)
        )
        imu = robot.read_imu()
        imu_ok = imu is not None and now - imu.stamp <= FRESH
        odometry_ok = now - robot.read_odometry().stamp <= FRESH
        power_ok = bool(robot.read_battery().voltage > 0.0)
        return {
            "sensor_core": laser and imu_ok,
            "motor_core_right": odometry_ok,
            "motor_core_left": odometry_ok,
            "radio_core": self._radio_ok,
            "power_core": power_ok,
            "laser": laser,
            "IMU": imu_ok,
            "CAN": odometry_ok,
        }
