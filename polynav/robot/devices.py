"""The robot's peripherals besides the base: what a vendor's "system" API drives.

A mobile base (:class:`~polynav.robot.interface.Robot`) drives and senses; robots also carry a
speaker, IO ports, environment sensors, a slide table or a jacking mechanism, cameras, and run
calibration and software-update procedures. Each is a small protocol here, so a real backend can
supply its own implementation and the rest of polynav cannot tell it from the simulator's
(:mod:`polynav.robot.sim.devices`). A device advances on the runtime's clock: it is handed
``now`` (simulated seconds on the simulator) and never reads the wall clock.

The protocols hold few methods; the readings are frozen dataclasses in SI units. A long-running
action (a slide move, a video recording) is a :class:`DeviceJob` the caller polls.
"""

from __future__ import annotations

import enum
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Protocol

from polynav.robot.interface import LaserScan, Odometry


class JobState(enum.Enum):
    """Where a device job stands."""

    WORKING = "working"
    COMPLETE = "complete"
    CANCELLED = "cancelled"
    ERROR = "error"


@dataclass(frozen=True, slots=True)
class DeviceJob:
    """A device action that takes time: ``progress`` in 0..1, and why it ended in ERROR."""

    job_id: str
    kind: str
    state: JobState
    progress: float
    started: float
    reason: str = ""


class AxisMode(enum.IntEnum):
    """How a move is given (the vendors' action modes)."""

    JOG = 0  # run at ``speed`` for ``duration`` seconds
    POSITION = 1  # go to ``target`` [m or rad] from the zero point
    HOME = 2  # find the zero point
    RATIO = 3  # go to ``target`` in 0..1 of the travel


@dataclass(frozen=True, slots=True)
class AxisState:
    """A slide, lift or turntable: ``homed`` once it found its zero point; ``position`` [m or
    rad] from zero and ``ratio`` of the travel are meaningful only once homed; ``fault`` when
    it stopped on an error."""

    homed: bool
    fault: bool
    position: float
    ratio: float
    moving: bool


class Axis(Protocol):
    """One driven axis (slide table, jacking height, jacking rotation)."""

    def state(self, now: float) -> AxisState: ...

    def move(
        self, now: float, mode: AxisMode, *, target: float = 0.0, speed: float = 0.0,
        duration: float = 0.0,
    ) -> DeviceJob:
        """Start a move (``speed`` 0 = the axis's default); replaces a running one.

        Raises:
            InvalidRequest: a target outside the travel, a negative speed, a jog without time.
        """
        ...

    def job(self, now: float, job_id: str) -> DeviceJob | None: ...

    def stop(self, now: float) -> None: ...


@dataclass(frozen=True, slots=True)
class EnvReading:
    """Temperature [°C], relative humidity [%], smoke [ppm], particulates [µg/m³],
    combustible gas [ppm of LEL] and noise [dB]."""

    stamp: float
    temperature: float
    humidity: float
    smoke: float
    pm1_0: float
    pm2_5: float
    pm10: float
    lel: float
    noise: float


@dataclass(frozen=True, slots=True)
class AirReading:
    """Temperature [°C], relative humidity [%], CO2 [ppm] and illuminance [lux]."""

    stamp: float
    temperature: float
    humidity: float
    co2: float
    illuminance: float


class EnvironmentSensors(Protocol):
    def read_env(self, now: float) -> EnvReading: ...

    def read_air(self, now: float) -> AirReading: ...


class Buzzer(Protocol):
    """The chassis buzzer (an alarm a remote operator switches on and off)."""

    @property
    def on(self) -> bool: ...

    def set(self, now: float, on: bool) -> None: ...


class Speaker(Protocol):
    """Speech output: a sentence plays for a while, a new one interrupts it."""

    def say(self, now: float, text: str, duration: float) -> None: ...

    def stop(self, now: float) -> bool:
        """Stop playing; whether something was playing."""
        ...

    def playing(self, now: float) -> bool: ...

    @property
    def volume(self) -> int:
        """Volume [%]."""
        ...

    def set_volume(self, percent: int) -> None: ...


class IoPorts(Protocol):
    """A bank of digital outputs (and inputs): ``None`` = an output never set."""

    def outputs(self) -> Sequence[int | None]: ...

    def inputs(self) -> Sequence[int]: ...

    @property
    def output_ports(self) -> range: ...

    @property
    def input_ports(self) -> range: ...

    def set_output(self, port: int, level: int) -> None:
        """Raises: InvalidRequest: no such output port, or a level other than 0/1."""
        ...

    def set_pwm(self, port: int, frequency: int, duty: int) -> None:
        """A PWM signal of ``frequency`` [Hz] and ``duty`` [%] on an output."""
        ...

    def set_servo(self, port: int, angle: int) -> None:
        """A servo pulse for ``angle`` [deg] on an output."""
        ...


class CalibrationStatus(enum.Enum):
    FREE = "FREE"
    CALIBRATING = "CALIBRATING"
    CALIBRATED = "CALIBRATED"


class Calibration(Protocol):
    """A calibration procedure: start, observe the robot moving, then commit or cancel."""

    def status(self) -> CalibrationStatus: ...

    @property
    def accuracy(self) -> float:
        """Quality of the result [0..100] once CALIBRATED (0 before)."""
        ...

    def start(self, now: float) -> None:
        """Raises: Conflict: already calibrating or a precondition is missing."""
        ...

    def cancel(self) -> bool: ...

    def complete(self) -> None:
        """Commit the result. Raises: Conflict: not CALIBRATED."""
        ...

    def observe(self, now: float, odometry: Odometry, scan: LaserScan | None) -> None: ...


class ImuCalibrator(Protocol):
    """Gyroscope bias calibration: the robot stands still for a while."""

    @property
    def running(self) -> bool: ...

    def start(self, now: float, odometry: Odometry) -> None:
        """Raises: Conflict: the robot moves or a calibration runs."""
        ...

    def observe(self, now: float, odometry: Odometry, scan: LaserScan | None) -> None: ...


class Camera(Protocol):
    """An on-board camera: one frame as it sees the world now, encoded (PNG or JPEG)."""

    def capture(self, now: float, *, view: str, fmt: str) -> bytes:
        """Raises: InvalidRequest: unknown view or format."""
        ...


@dataclass(frozen=True, slots=True)
class PtzPose:
    """Pan and tilt in -1..1 and zoom in 0..1 (the ONVIF normalized space)."""

    pan: float
    tilt: float
    zoom: float


class PtzCamera(Protocol):
    """A pan-tilt-zoom network camera (ONVIF)."""

    address: tuple[str, int]

    def check_login(self, ip: str, port: int, username: str, password: str) -> None:
        """Raises: InvalidRequest: no camera there (empty ``ip``: the first one found), or
        the camera refuses the credentials."""
        ...

    def pose(self, now: float) -> PtzPose: ...

    def move_to(self, now: float, pose: PtzPose) -> None: ...

    def move_speed(self, now: float, pan: float, tilt: float, zoom: float) -> None: ...

    def goto_preset(self, now: float, name: str) -> None: ...

    def presets(self) -> Mapping[str, PtzPose]: ...

    def snapshot(self, now: float) -> bytes: ...


class SoftwareUpdate(Protocol):
    """The robot's software updater."""

    def check(self) -> str | None:
        """The version available, or ``None``."""
        ...

    def start(self) -> None:
        """Raises: Conflict: nothing to update to."""
        ...

    def cancel(self) -> bool: ...

    def log(self) -> str: ...


@dataclass(frozen=True, slots=True, eq=False)
class DeviceSet:
    """Every peripheral of one robot, as a backend supplies them.

    ``calibrations`` and ``imu_calibration`` observe the robot's motion every control period
    (:meth:`observe`); the other devices advance themselves to the ``now`` they are handed.
    """

    slide: Axis
    jacking: Axis
    jacking_rotation: Axis
    sensors: EnvironmentSensors
    speaker: Speaker
    buzzer: Buzzer
    io: IoPorts
    expansion_io: IoPorts
    voice_io: IoPorts
    camera: Camera
    ptz_camera: PtzCamera
    camera_calibration: Calibration
    lidar_calibration: Calibration
    imu_calibration: ImuCalibrator
    software_update: SoftwareUpdate

    def observe(self, now: float, odometry: Odometry, scan: LaserScan | None) -> None:
        """One control period of the robot's motion, for the procedures that watch it."""
        self.camera_calibration.observe(now, odometry, scan)
        self.lidar_calibration.observe(now, odometry, scan)
        self.imu_calibration.observe(now, odometry, scan)
