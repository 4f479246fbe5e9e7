"""Simulated calibration procedures, driven by how the robot actually moves.

The vendors' procedures ask the operator to drive the robot around and wait; here the state
machines watch the wheel odometry and the lidar (:meth:`observe`, every control period) and
finish when the robot has done what the procedure needs:

* **Camera** (angle and position of the camera): ``FREE`` -> ``start`` -> ``CALIBRATING``; the
  robot must drive a closed loop (at least ``LOOP_LENGTH`` metres and back within
  ``LOOP_CLOSE`` of where it started, as a visual SLAM needs a loop closure), then on for
  ``AFTER_LOOP`` metres -> ``CALIBRATED``, with an accuracy from how well the loop closed.
  ``complete`` (only when CALIBRATED) commits and returns to ``FREE``; ``cancel`` aborts.
* **Lidar** (its mounting pose): only after a committed camera calibration. It needs
  ``LIDAR_DISTANCE`` metres driven and ``LIDAR_TURN`` radians turned while the scan sees clear
  boundaries (at least ``LIDAR_RETURNS`` of its beams return).
* **IMU** (gyroscope bias): the robot must stand still; it takes ``IMU_TIME`` seconds, and moving
  in that time fails it.
"""

from __future__ import annotations

import logging
import math

import numpy as np

from polynav.errors import Conflict
from polynav.geometry import Pose2D, angle_diff
from polynav.robot.devices import CalibrationStatus
from polynav.robot.interface import LaserScan, Odometry

log = logging.getLogger(__name__)

LOOP_LENGTH = 4.0  # [m] the shortest loop a camera calibration accepts
LOOP_CLOSE = 0.5  # [m] how near the start a loop must come back
AFTER_LOOP = 1.0  # [m] driven on after the loop closed
LIDAR_DISTANCE = 2.0  # [m]
LIDAR_TURN = math.pi  # [rad]
LIDAR_RETURNS = 0.5  # share of beams with a return
IMU_TIME = 5.0  # [s]
STILL = 0.01  # [m/s, rad/s] below this the robot stands still


class _Tracker:
    """Path length and turning from successive odometry poses."""

    def __init__(self) -> None:
        self.last: Pose2D | None = None
        self.length = 0.0
        self.turned = 0.0

    def update(self, pose: Pose2D) -> tuple[float, float]:
        if self.last is None:
            self.last = pose
            return 0.0, 0.0
        step = pose.distance_to(self.last)
        turn = abs(angle_diff(pose.theta, self.last.theta))
        self.last = pose
        self.length += step
        self.turned += turn
        return step, turn


class CameraCalibration:
    """Implements :class:`~polynav.robot.devices.Calibration` for the camera."""

    def __init__(self) -> None:
        self._status = CalibrationStatus.FREE
        self._accuracy = 0.0
        self.committed = False
        self._start: Pose2D | None = None
        self._track = _Tracker()
        self._closed_at: float | None = None  # path length when the loop closed

    def status(self) -> CalibrationStatus:
        return self._status

    @property
    def accuracy(self) -> float:
        return self._accuracy if self._status is CalibrationStatus.CALIBRATED else 0.0

    def start(self, now: float) -> None:
        """Raises: Conflict: already calibrating."""
        if self._status is CalibrationStatus.CALIBRATING:
            raise Conflict("camera calibration is already running")
        self._status = CalibrationStatus.CALIBRATING
        self._start, self._track, self._closed_at = None, _Tracker(), None
        log.info("camera calibration started at t=%.2f", now)

    def cancel(self) -> bool:
        was = self._status is not CalibrationStatus.FREE
        self._status = CalibrationStatus.FREE
        return was

    def complete(self) -> None:
        """Raises: Conflict: not CALIBRATED."""
        if self._status is not CalibrationStatus.CALIBRATED:
            raise Conflict(f"camera calibration is {self._status.value}, not CALIBRATED")
        self.committed = True
        self._status = CalibrationStatus.FREE
        log.info("camera calibration committed (accuracy %.1f)", self._accuracy)

    def observe(self, now: float, odometry: Odometry, scan: LaserScan | None) -> None:
        if self._status is not CalibrationStatus.CALIBRATING:
            return
        pose = odometry.pose
        if self._start is None:
            self._start = pose
        self._track.update(pose)
        if self._closed_at is None:
            gap = pose.distance_to(self._start)
            if self._track.length >= LOOP_LENGTH and gap <= LOOP_CLOSE:
                self._closed_at = self._track.length
                # A tighter closure over a longer loop is a better calibration.
                self._accuracy = round(100.0 * (1.0 - 0.5 * gap / LOOP_CLOSE), 1)
        elif self._track.length - self._closed_at >= AFTER_LOOP:
            self._status = CalibrationStatus.CALIBRATED
            log.info("camera calibration done at t=%.2f", now)


class LidarCalibration:
    """Implements :class:`~polynav.robot.devices.Calibration` for the lidar mounting."""

    def __init__(self, camera: CameraCalibration) -> None:
        self._camera = camera
        self._status = CalibrationStatus.FREE
        self._track = _Tracker()
        self._distance = 0.0
        self._turn = 0.0
        self._beams = 0
        self._returns = 0
        self.committed = False

    def status(self) -> CalibrationStatus:
        return self._status

    @property
    def accuracy(self) -> float:
        if self._status is not CalibrationStatus.CALIBRATED or not self._beams:
            return 0.0
        return round(100.0 * self._returns / self._beams, 1)

    def start(self, now: float) -> None:
        """Raises: Conflict: already calibrating, or the camera was never calibrated."""
        if not self._camera.committed:
            raise Conflict("calibrate the camera first: lidar calibration needs it")
        if self._status is CalibrationStatus.CALIBRATING:
            raise Conflict("lidar calibration is already running")
        self._status = CalibrationStatus.CALIBRATING
        self._track, self._distance, self._turn = _Tracker(), 0.0, 0.0
        self._beams = self._returns = 0
        log.info("lidar calibration started at t=%.2f", now)

    def cancel(self) -> bool:
        was = self._status is not CalibrationStatus.FREE
        self._status = CalibrationStatus.FREE
        return was

    def complete(self) -> None:
        """Raises: Conflict: not CALIBRATED."""
        if self._status is not CalibrationStatus.CALIBRATED:
            raise Conflict(f"lidar calibration is {self._status.value}, not CALIBRATED")
        self.committed = True
        self._status = CalibrationStatus.FREE

    def observe(self, now: float, odometry: Odometry, scan: LaserScan | None) -> None:
        if self._status is not CalibrationStatus.CALIBRATING:
            return
        step, turn = self._track.update(odometry.pose)
        if scan is None or now - scan.stamp > 1.0:
            return
        returns = int(np.count_nonzero(np.isfinite(scan.ranges)))
        if returns < LIDAR_RETURNS * scan.ranges.shape[0]:
            return  # no clear boundaries in view: this stretch does not count
        self._beams += int(scan.ranges.shape[0])
        self._returns += returns
        self._distance += step
        self._turn += turn
        if self._distance >= LIDAR_DISTANCE and self._turn >= LIDAR_TURN:
            self._status = CalibrationStatus.CALIBRATED
            log.info("lidar calibration done at t=%.2f", now)


class ImuCalibration:
    """Gyroscope bias estimation: ``IMU_TIME`` seconds standing still."""

    def __init__(self) -> None:
        self._until: float | None = None
        self.failed = False
        self.calibrated_at: float | None = None

    @property
    def running(self) -> bool:
        return self._until is not None

    def start(self, now: float, odometry: Odometry) -> None:
        """Raises: Conflict: the robot moves, or a calibration runs."""
        if self._until is not None:
            raise Conflict("IMU calibration is already running")
        if _moving(odometry):
            raise Conflict("the robot must stand still to calibrate the IMU")
        self._until = now + IMU_TIME
        self.failed = False

    def observe(self, now: float, odometry: Odometry, scan: LaserScan | None) -> None:
        if self._until is None:
            return
        if _moving(odometry):
            self._until = None
            self.failed = True
            log.warning("IMU calibration failed: the robot moved")
        elif now >= self._until:
            self._until = None
            self.calibrated_at = now


def _moving(odometry: Odometry) -> bool:
    return abs(odometry.twist.linear) > STILL or abs(odometry.twist.angular) > STILL
