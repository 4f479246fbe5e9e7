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
class PoseUncertainty:
    """How well a localizer knows its pose: one standard deviation of its error.

    Quality says whether the scan fits the map; this says where the pose may still be wrong.
    They differ where it matters for arriving: in an open hall beyond the lidar's range the
    scan fits (nothing contradicts it) while the position is dead reckoning, metres from the
    last wall that fixed it.

    Attributes:
        position: standard deviation of the position along its worst-known direction [m] (a
            corridor's length, say), not an average over directions.
        heading: standard deviation of the heading [rad].
    """

    position: float
    heading: float


@dataclass(frozen=True, slots=True)
class LocalizationEstimate:
    """Pose on the map, a quality figure in [0, 1] (1 = scan fits the map perfectly), state,
    and the pose's uncertainty (``None``: the localizer does not say, so nobody may rely on a
    precise pose)."""

    stamp: float
    pose: Pose2D
    quality: float
    state: LocalizationState
    uncertainty: PoseUncertainty | None = None


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
