"""What a localizer is and what it reports."""

from __future__ import annotations

import enum
from dataclasses import dataclass
from typing import Protocol

from polynav.geometry import Pose2D
from polynav.maps.map import Map
from polynav.robot.interface import ImuReading, LaserScan, Odometry


class LocalizationState(enum.Enum):
    UNINITIALIZED = "uninitialized"
    TRACKING = "tracking"
    LOST = "lost"


@dataclass(frozen=True, slots=True)
class LocalizationEstimate:
    """Pose on the map, a quality figure in [0, 1] (1 = scan fits the map perfectly), state."""

    stamp: float
    pose: Pose2D
    quality: float
    state: LocalizationState


class Localizer(Protocol):
    def set_map(self, grid: Map) -> None:
        """Localize against ``grid`` from now on; the state becomes UNINITIALIZED."""
        ...

    def initialize(self, pose: Pose2D, now: float) -> None:
        """Start (or restart) tracking near ``pose``; relocalizes within about 1 m / 30°."""
        ...

    def update(
        self,
        odometry: Odometry,
        imu: ImuReading | None,
        scan: LaserScan | None,
        now: float,
    ) -> LocalizationEstimate:
        """Predict with odometry/IMU, correct with ``scan`` when given, return the estimate."""
        ...

    @property
    def estimate(self) -> LocalizationEstimate: ...
