"""The simulator's settings: one flat, frozen dataclass in SI units (STYLE R10).

Defaults describe a typical indoor service robot: a 0.5 m round differential-drive base, a 360°
2-D lidar at 15 Hz, wheel odometry with a few per cent of noise, a gyro with a small bias, and a
20 Ah battery.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

from polynav.docking.shape import DockShape
from polynav.errors import ConfigError


@dataclass(frozen=True, slots=True)
class SimConfig:
    """How the simulated robot and its sensors behave.

    Attributes:
        robot_radius: the base's footprint, a disk [m]; with ``footprint_polygon`` the radius
            of the smallest disk about the centre that holds the polygon (people keep clear of
            it).
        footprint_polygon: the base's outline as polygon vertices [m] in the base frame (x
            forward, y left), or ``()`` for the disk of ``robot_radius``; contact with walls is
            then checked against the polygon (see :mod:`polynav.robot.sim.collision`).
        max_linear_velocity: forward and backward speed clamp [m/s].
        max_angular_velocity: turn-rate clamp [rad/s].
        linear_acceleration: speeding-up rate [m/s²].
        linear_deceleration: braking rate [m/s²], used whenever the base slows down, e-stop
            included (the e-stop brakes at this, the largest rate the base has).
        angular_acceleration: turn-rate increase [rad/s²].
        angular_deceleration: turn-rate decrease [rad/s²], e-stop included.
        physics_rate: physics steps per simulated second [Hz]; one :meth:`Simulation.step`.
        lidar_x: the lidar's mount on the base, forward of the centre [m] ...
        lidar_y: ... to the left of it [m] ...
        lidar_theta: ... and turned by this angle [rad] (scans carry it as ``sensor_pose``).
        lidar_beams: beams per scan.
        lidar_fov: field of view [rad]; a full circle (2π) spaces beams over [-π, π).
        lidar_range: longest return [m]; farther is ``inf``.
        lidar_range_min: shortest return [m]; nearer is ``inf`` (no valid return).
        lidar_range_noise: standard deviation of Gaussian range noise [m].
        lidar_rate: scans per second [Hz]; at most ``physics_rate``.
        odom_translation_noise: std of the multiplicative noise on each step's travel [fraction].
        odom_rotation_noise: std of the multiplicative noise on each step's turn [fraction].
        odom_translation_additive: std of the additive noise per moving step [m].
        odom_rotation_additive: std of the additive noise per moving step [rad].
        imu_rate: IMU samples per second [Hz]; at most ``physics_rate``.
        imu_yaw_rate_noise: std of the gyro's white noise [rad/s].
        imu_yaw_rate_bias: std of the gyro's constant bias, drawn once per run [rad/s].
        imu_acceleration_noise: std of the accelerometer's white noise [m/s²].
        battery_capacity: charge when full [Ah].
        battery_idle_drain: drain while powered [%/h].
        battery_drain_per_metre: extra drain per metre of wheel travel [%/m].
        battery_charge_rate: gain while docked on a charger [%/h].
        battery_start_percent: charge at the start [%].
        battery_empty_voltage: pack voltage at 0 % [V] (at rest).
        battery_full_voltage: pack voltage at 100 % [V] (at rest; the charger holds it).
        battery_internal_resistance: the pack's resistance [ohm]: the voltage sags under load
            and the charge current tapers near full.
        dock_distance_tolerance: the base touches a charger's contacts when it stands this close
            to a charger point's position [m] ...
        dock_heading_tolerance: ... facing that point's heading within this angle [rad].
        charger_plate_width: the chargers' front plates are this wide [m] ...
        charger_notch_width: ... with a V notch this wide [m] ...
        charger_notch_depth: ... and this deep [m] (:class:`~polynav.docking.shape.DockShape`).
        person_pause: a walker pauses this long at the ends of its route [s].
        person_stop_distance: a walker stops rather than come within this much walking [m] of
            contact with the robot.
        person_patience: a walker held up this long by robots turns round [s] (walking on
            wears a hold-up off at a quarter of the rate).
        sign_camera_range: how far [m] the camera that spots "no entry" signs sees (0: the
            robot has none).
        sign_camera_fov: how wide [rad] it sees, centred on the base's heading.
        collision_release_distance: a contact ends, and the next one is a new collision, once
            the robot is this far clear of every obstacle [m].
    """

    robot_radius: float = 0.25
    footprint_polygon: tuple[tuple[float, float], ...] = ()
    max_linear_velocity: float = 1.0
    max_angular_velocity: float = 2.0
    linear_acceleration: float = 1.0
    linear_deceleration: float = 2.5
    angular_acceleration: float = 3.0
    angular_deceleration: float = 5.0
    physics_rate: float = 50.0
    lidar_x: float = 0.0
    lidar_y: float = 0.0
    lidar_theta: float = 0.0
    lidar_beams: int = 360
    lidar_fov: float = 2.0 * math.pi
    lidar_range: float = 12.0
    lidar_range_min: float = 0.05
    lidar_range_noise: float = 0.01
    lidar_rate: float = 15.0
    odom_translation_noise: float = 0.02
    odom_rotation_noise: float = 0.02
    odom_translation_additive: float = 0.0002
    odom_rotation_additive: float = 0.0002
    imu_rate: float = 50.0
    imu_yaw_rate_noise: float = 0.005
    imu_yaw_rate_bias: float = 0.002
    imu_acceleration_noise: float = 0.05
    battery_capacity: float = 20.0
    battery_idle_drain: float = 3.0
    battery_drain_per_metre: float = 0.005
    battery_charge_rate: float = 40.0
    battery_start_percent: float = 80.0
    battery_empty_voltage: float = 22.0
    battery_full_voltage: float = 29.4
    battery_internal_resistance: float = 0.1
    dock_distance_tolerance: float = 0.1
    dock_heading_tolerance: float = 0.3
    charger_plate_width: float = 0.6
    charger_notch_width: float = 0.3
    charger_notch_depth: float = 0.1
    person_pause: float = 2.0
    person_stop_distance: float = 0.3
    person_patience: float = 15.0
    collision_release_distance: float = 0.05
    sign_camera_range: float = 0.0
    sign_camera_fov: float = 0.0

    def __post_init__(self) -> None:
        positive = (
            "robot_radius", "max_linear_velocity", "max_angular_velocity", "linear_acceleration",
            "linear_deceleration", "angular_acceleration", "angular_deceleration",
            "physics_rate", "lidar_range", "lidar_rate", "imu_rate", "battery_capacity",
            "battery_full_voltage", "collision_release_distance",
        )
        non_negative = (
            "lidar_range_min", "lidar_range_noise", "odom_translation_noise",
            "odom_rotation_noise", "odom_translation_additive", "odom_rotation_additive",
            "imu_yaw_rate_noise", "imu_yaw_rate_bias", "imu_acceleration_noise",
            "battery_idle_drain", "battery_drain_per_metre", "battery_charge_rate",
            "battery_empty_voltage", "battery_internal_resistance", "dock_distance_tolerance",
            "dock_heading_tolerance", "sign_camera_range", "sign_camera_fov",
            "person_pause", "person_stop_distance", "person_patience",
        )
        for f in fields(self):
            value = getattr(self, f.name)
            if isinstance(value, float | int) and not math.isfinite(value):
                _fail(f.name, f"must be finite, got {value}")
        if self.footprint_polygon:
            if len(self.footprint_polygon) < 3:
                _fail("footprint_polygon", "needs at least 3 vertices")
            reach = max(math.hypot(x, y) for x, y in self.footprint_polygon)
            if reach > self.robot_radius + 1e-9:
                _fail("robot_radius", f"must hold the polygon: at least {reach:g}")
        for name in positive:
            if not getattr(self, name) > 0.0:
                _fail(name, f"must be > 0, got {getattr(self, name)}")
        for name in non_negative:
            if not getattr(self, name) >= 0.0:
                _fail(name, f"must be >= 0, got {getattr(self, name)}")
        if isinstance(self.lidar_beams, bool) or not isinstance(self.lidar_beams, int) or (
            self.lidar_beams < 1
        ):
            _fail("lidar_beams", f"must be an integer >= 1, got {self.lidar_beams!r}")
        if not 0.0 < self.lidar_fov <= 2.0 * math.pi:
            _fail("lidar_fov", f"must be within (0, 2π], got {self.lidar_fov}")
        if not self.lidar_range_min < self.lidar_range:
            _fail("lidar_range_min", f"must be below lidar_range ({self.lidar_range})")
        for name in ("lidar_rate", "imu_rate"):
            if getattr(self, name) > self.physics_rate:
                _fail(name, f"must be <= physics_rate ({self.physics_rate}): sensors sample on "
                            "physics steps")
        if not 0.0 <= self.battery_start_percent <= 100.0:
            _fail("battery_start_percent", f"must be within 0..100, got "
                                           f"{self.battery_start_percent}")
        try:
            self.charger_plate  # noqa: B018 - validates the plate's sizes
        except ConfigError as exc:
            _fail("charger_plate_width", str(exc))
        if not self.battery_empty_voltage < self.battery_full_voltage:
            _fail("battery_empty_voltage",
                  f"must be below battery_full_voltage ({self.battery_full_voltage})")

    @property
    def charger_plate(self) -> DockShape:
        """The chargers' front plate."""
        return DockShape(self.charger_plate_width, self.charger_notch_width,
                         self.charger_notch_depth)

    @property
    def front_reach(self) -> float:
        """How far [m] ahead of the centre the body's front is (where a charger's face meets
        it): the disk's radius, or the polygon's foremost vertex."""
        if self.footprint_polygon:
            return max(x for x, _ in self.footprint_polygon)
        return self.robot_radius

    @property
    def physics_period(self) -> float:
        """Length of one physics step [s]."""
        return 1.0 / self.physics_rate


def _fail(field: str, reason: str) -> None:
    raise ConfigError(f"sim.{field}", reason)
