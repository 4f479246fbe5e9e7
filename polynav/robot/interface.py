"""The robot interface every backend implements, and the sensor readings it returns.

The simulator and the rosbridge driver both implement :class:`Robot`; nothing above this layer can
tell them apart. Readings carry the backend's timestamp (simulated seconds in the simulator).
"""

from __future__ import annotations

import enum
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np
import numpy.typing as npt

from polynav.clock import Clock
from polynav.geometry import Pose2D, Twist


@dataclass(frozen=True, slots=True)
class Odometry:
    """Wheel odometry: pose in the odometry frame (drifts) and measured velocity."""

    stamp: float
    pose: Pose2D
    twist: Twist


@dataclass(frozen=True, slots=True, eq=False)
class LaserScan:
    """One 2-D lidar sweep, ROS ``sensor_msgs/LaserScan`` style.

    ``ranges[k]`` is the distance [m] along ``angle_min + k * angle_increment`` (robot frame, after
    ``sensor_pose``); ``inf`` means no return within ``range_max``.
    """

    stamp: float
    angle_min: float
    angle_increment: float
    range_min: float
    range_max: float
    ranges: npt.NDArray[np.float32]
    sensor_pose: Pose2D = Pose2D()

    @property
    def angles(self) -> npt.NDArray[np.float64]:
        """Beam angles [rad] in the sensor frame."""
        steps = np.arange(self.ranges.shape[0], dtype=np.float64)
        return np.asarray(self.angle_min + self.angle_increment * steps, dtype=np.float64)


@dataclass(frozen=True, slots=True)
class ImuReading:
    """Planar IMU: integrated yaw [rad], yaw rate [rad/s], forward acceleration [m/s²]."""

    stamp: float
    yaw: float
    angular_velocity: float
    linear_acceleration: float


@dataclass(frozen=True, slots=True)
class BatteryState:
    """Battery charge [%], voltage [V], current [A] (negative while discharging), charging, the
    charger's output voltage [V] (0 when not on a charger) and the current the computers and
    sensors draw [A]."""

    stamp: float
    percent: float
    voltage: float
    current: float
    charging: bool
    charger_voltage: float = 0.0
    electronics_current: float = 0.0


@dataclass(frozen=True, slots=True)
class PersonDetection:
    """A person a leg tracker sees: position [m] and own velocity [m/s] in the robot frame
    (+x forward, +y left); ``track_id`` stays the same while the person stays in view."""

    track_id: int
    x: float
    y: float
    vx: float
    vy: float


@dataclass(frozen=True, slots=True)
class SignDetection:
    """A "no entry" sign a sign camera sees: where it stands [m] in the robot frame (+x
    forward, +y left)."""

    x: float
    y: float


@runtime_checkable
class SignCamera(Protocol):
    """A base with a camera that spots "no entry" signs (only some robots have one)."""

    def read_signs(self) -> Sequence[SignDetection]:
        """The signs the camera sees now."""
        ...


class DockLink(enum.Enum):
    """The data link a charger and a robot keep over their contacts."""

    NONE = "none"  # no contact: nothing exchanged
    VALID = "valid"  # frames exchanged and checked: the charger may switch its current on
    INVALID = "invalid"  # frames arrive but fail their check


@dataclass(frozen=True, slots=True)
class DockSignals:
    """A base's docking sensors: whether its infrared receiver sees a charger's beacon, whether
    its contacts touch a charger's, and how the data link over them stands."""

    beacon: bool
    contact: bool
    link: DockLink


class Robot(Protocol):
    """What polynav needs from a mobile base."""

    def drive(self, twist: Twist) -> None:
        """Command a body velocity; the base applies its own acceleration limits."""
        ...

    def read_odometry(self) -> Odometry: ...

    def read_scan(self) -> LaserScan | None:
        """The newest scan, or ``None`` before the first one."""
        ...

    def read_imu(self) -> ImuReading | None: ...

    def read_battery(self) -> BatteryState: ...

    def estop_pressed(self) -> bool:
        """True while the hardware emergency-stop button is pressed."""
        ...

    def read_people(self) -> Sequence[PersonDetection]:
        """The people the base's leg tracker sees now; empty for a base without one."""
        ...

    def read_dock(self) -> DockSignals | None:
        """The docking sensors now; ``None`` for a base without them (docking then goes by the
        scan and the charging current alone)."""
        ...


class Backend(Protocol):
    """A robot with its clock: what the runtime runs on (the simulator, or a real robot reached
    over rosbridge). The runtime's loop calls :meth:`step` once per physics period."""

    @property
    def robot(self) -> Robot: ...

    @property
    def clock(self) -> Clock:
        """The backend's time: simulated seconds, or the real robot's clock."""
        ...

    @property
    def physics_period(self) -> float:
        """Seconds of :attr:`clock` per :meth:`step`."""
        ...

    def step(self) -> None:
        """Let one physics period pass: the simulator computes it; a real robot's backend waits
        for it (briefly: it returns within a fraction of a second even when the robot is away,
        so that the loop goes on running commands)."""
        ...
