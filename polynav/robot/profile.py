"""Robot profiles: one YAML file (``robot.yaml``) that says what the robot is.

A profile describes the body (a footprint: a circle or a polygon in the base frame), how fast it
may drive and turn and how hard it may speed up and brake, its lidar (where it sits on the base,
range, field of view, beams, rate, noise), its odometry and IMU noise, and where the charger
touches it. The simulator builds its base and sensors from it (:meth:`RobotProfile.sim_config`)
and the navigation stack its costmap inflation and controller limits
(:func:`polynav.nav.stack.stack_config_for`), so the robot that is simulated, planned for and
driven is one robot.

The file, every key optional except ``name`` and ``footprint`` (units SI, angles radians)::

    name: research-base
    description: a rectangular research base
    footprint:
      polygon: [[0.255, 0.215], [-0.255, 0.215], [-0.255, -0.215], [0.255, -0.215]]
      # or: radius: 0.25
    limits:
      max_linear_velocity: 2.0       # m/s, forward and backward
      max_angular_velocity: 3.0      # rad/s
      linear_acceleration: 1.5       # m/s²
      linear_deceleration: 3.0
      angular_acceleration: 4.0      # rad/s²
      angular_deceleration: 6.0
    cruise:                          # how navigation drives by default, within the limits:
      linear_velocity: 2.0           #  speeds are the settings' defaults,
      angular_velocity: 2.5
      linear_acceleration: 1.2       #  accelerations the controller's
      linear_deceleration: 2.0
      angular_acceleration: 3.0
    lidar:
      pose: {x: 0.15, y: 0.0, theta: 0.0}   # on the base, inside the footprint
      range_min: 0.05
      range_max: 12.0
      fov: 6.2832
      beams: 360
      rate: 15.0
      noise: 0.01                    # range noise std [m]
    odometry: {translation_noise: 0.02, rotation_noise: 0.02,
               translation_additive: 0.0002, rotation_additive: 0.0002}
    imu: {rate: 50.0, yaw_rate_noise: 0.005, yaw_rate_bias: 0.002, acceleration_noise: 0.05}
    charger: {distance_tolerance: 0.1, heading_tolerance: 0.3,   # contacts touch within
              plate_width: 0.6, notch_width: 0.3, notch_depth: 0.1}  # the plate the lidar sees
    reverse: {allowed: true, rear_view: 12.0}   # may it back up in a recovery; how far [m] its
                                               # sensors see behind it (default: the lidar's
                                               # range if it sees behind, else 0)
    sign_camera: {range: 4.0, fov: 1.2}   # a camera that spots "no entry" signs ahead (only some
                                          # robots: left out, the robot has none)
    payload: {max_mass: 50.0,             # what it can carry on its jack or latch [kg] and how
              linear_velocity: 0.4,       # it drives loaded (cruise speeds and acceleration,
              angular_velocity: 1.0,      # within the limits); left out, it carries nothing
              linear_acceleration: 0.4}

Frame conventions (REP 103): x forward, y left, the base's origin is its centre of rotation. A
polygon is listed in order (either winding), must not cross itself, and must contain the
origin (a base turns about a point of itself); the lidar sits inside the footprint.

Any fault is a :class:`ProfileError` naming the field (``robot.limits.max_linear_velocity: must
be > 0, got -1``); unknown keys are faults too, since a misspelt key silently ignored would drive
a robot with the wrong limits.
"""

from __future__ import annotations

import logging
import math
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any

import yaml

from polynav import safe_yaml
from polynav.docking.shape import DockShape
from polynav.errors import ConfigError, InvalidRequest
from polynav.footprint import Footprint
from polynav.geometry import Pose2D
from polynav.robot.rosbridge.config import BridgeConfig
from polynav.robot.sim.config import SimConfig

log = logging.getLogger(__name__)

PROFILES_DIR = Path(__file__).resolve().parent / "profiles"
"""Where the built-in profiles live, one ``NAME.yaml`` each."""

DEFAULT_PROFILE = "demo"

# A polygon's edges keep at least this far [m] from the base origin: a centre of rotation on the
# outline is no body to turn.
_MIN_INSCRIBED = 1e-3


class ProfileError(InvalidRequest):
    """A robot profile is malformed or inconsistent; ``field`` is its full key (``robot.…``)."""

    def __init__(self, field: str, reason: str) -> None:
        super().__init__(field if field.startswith("robot") else f"robot.{field}", reason)


# -- the parts ----------------------------------------------------------------------------------


def footprint_document(footprint: Footprint) -> dict[str, Any]:
    """A footprint in the file's shape: ``{radius: r}`` or ``{polygon: [[x, y], ...]}``."""
    if footprint.is_circle:
        return {"radius": footprint.radius}
    return {"polygon": [[float(x), float(y)] for x, y in footprint.vertices]}


def footprint_polygon(footprint: Footprint) -> tuple[tuple[float, float], ...]:
    """A polygon footprint's vertices as a tuple (``()`` for a circle), for frozen configs."""
    return tuple((float(x), float(y)) for x, y in footprint.vertices)


@dataclass(frozen=True, slots=True)
class Limits:
    """Speed and acceleration limits of the base (SI units; see :class:`SimConfig`)."""

    max_linear_velocity: float = 1.0
    max_angular_velocity: float = 2.0
    linear_acceleration: float = 1.0
    linear_deceleration: float = 2.5
    angular_acceleration: float = 3.0
    angular_deceleration: float = 5.0


@dataclass(frozen=True, slots=True)
class Cruise:
    """How navigation drives unless an operator changes it, within :class:`Limits`: its speeds
    are the settings' defaults, its accelerations the controller's (gentler than the base can,
    so a loaded robot does not jerk)."""

    linear_velocity: float = 0.6
    angular_velocity: float = 1.5
    linear_acceleration: float = 0.8
    linear_deceleration: float = 1.2
    angular_acceleration: float = 3.0


@dataclass(frozen=True, slots=True)
class LidarSpec:
    """The 2-D lidar: its mount on the base and how it measures."""

    x: float = 0.0
    y: float = 0.0
    theta: float = 0.0
    range_min: float = 0.05
    range_max: float = 12.0
    fov: float = 2.0 * math.pi
    beams: int = 360
    rate: float = 15.0
    noise: float = 0.01


@dataclass(frozen=True, slots=True)
class OdometryNoise:
    """Wheel odometry noise (see :class:`SimConfig` ``odom_*``)."""

    translation_noise: float = 0.02
    rotation_noise: float = 0.02
    translation_additive: float = 0.0002
    rotation_additive: float = 0.0002


@dataclass(frozen=True, slots=True)
class ImuSpec:
    """The IMU's rate and noise (see :class:`SimConfig` ``imu_*``)."""

    rate: float = 50.0
    yaw_rate_noise: float = 0.005
    yaw_rate_bias: float = 0.002
    acceleration_noise: float = 0.05


@dataclass(frozen=True, slots=True)
class ChargerContact:
    """How precisely the base must stand on a charger point for its contacts to touch, and the
    shape of the charger's front plate that docking finds in the scan
    (:class:`~polynav.docking.shape.DockShape`)."""

    distance_tolerance: float = 0.1
    heading_tolerance: float = 0.3
    plate_width: float = 0.6
    notch_width: float = 0.3
    notch_depth: float = 0.1

    @property
    def plate(self) -> DockShape:
        """The plate's outline (raises ConfigError when inconsistent)."""
        return DockShape(self.plate_width, self.notch_width, self.notch_depth)


@dataclass(frozen=True, slots=True)
class Reverse:
    """Whether the base may drive backwards in a recovery (backing up, backing out of a pocket),
    and how far [m] behind it its sensors see; ``rear_view`` ``None`` takes the lidar's range
    when its field of view reaches behind the base, else 0 (blind behind)."""

    allowed: bool = True
    rear_view: float | None = None


@dataclass(frozen=True, slots=True)
class SignCamera:
    """A forward camera that spots "no entry" signs: how far [m] and how wide [rad] it sees
    (centred on the base's heading)."""

    range: float = 4.0
    fov: float = 1.2


@dataclass(frozen=True, slots=True)
class Payload:
    """What the robot can carry (a cart on its jacking axis, a cabin on its latch): the most
    mass [kg], and how it drives while loaded: cruise speeds [m/s, rad/s] and acceleration
    [m/s²], each at most the unloaded cruise's (a load shifts the centre of mass up)."""

    max_mass: float = 50.0
    linear_velocity: float = 0.4
    angular_velocity: float = 1.0
    linear_acceleration: float = 0.4


@dataclass(frozen=True, slots=True)
class RobotProfile:
    """One robot: body, limits, sensors and charger contact (see the module docstring).

    Build it with :func:`load_profile` or :func:`parse_profile`, which validate; a profile built
    directly is validated too (``__post_init__``).
    """

    name: str
    footprint: Footprint
    description: str = ""
    limits: Limits = field(default_factory=Limits)
    cruise: Cruise = field(default_factory=Cruise)
    lidar: LidarSpec = field(default_factory=LidarSpec)
    odometry: OdometryNoise = field(default_factory=OdometryNoise)
    imu: ImuSpec = field(default_factory=ImuSpec)
    charger: ChargerContact = field(default_factory=ChargerContact)
    reverse: Reverse = field(default_factory=Reverse)
    #: The camera that spots "no entry" signs; ``None``: the robot has none.
    sign_camera: SignCamera | None = None
    #: How the robot's ROS driver is reached over rosbridge (``polynav run --robot-bridge``):
    #: topic and frame names; ``None``: ROS's defaults.
    ros: BridgeConfig | None = None
    #: What the robot can carry and how it drives loaded; ``None``: it carries nothing.
    payload: Payload | None = None

    def __post_init__(self) -> None:
        _validate(self)

    @property
    def rear_view(self) -> float:
        """How far [m] behind the base its sensors see (:class:`Reverse`)."""
        if self.reverse.rear_view is not None:
            return self.reverse.rear_view
        # Seen behind when the lidar's field of view reaches straight back from its heading.
        behind = abs(math.remainder(math.pi - self.lidar.theta, 2.0 * math.pi))
        return self.lidar.range_max if self.lidar.fov / 2.0 >= behind - 1e-9 else 0.0

    @property
    def inscribed_radius(self) -> float:
        return self.footprint.inscribed_radius

    @property
    def circumscribed_radius(self) -> float:
        return self.footprint.circumscribed_radius

    def sim_config(self, base: SimConfig | None = None) -> SimConfig:
        """``base`` (default: :class:`SimConfig`'s defaults) with this robot's body, limits and
        sensors: the simulator then simulates this robot."""
        lim, lidar, odo, imu = self.limits, self.lidar, self.odometry, self.imu
        return replace(
            base or SimConfig(),
            robot_radius=self.footprint.circumscribed_radius,
            footprint_polygon=footprint_polygon(self.footprint),
            max_linear_velocity=lim.max_linear_velocity,
            max_angular_velocity=lim.max_angular_velocity,
            linear_acceleration=lim.linear_acceleration,
            linear_deceleration=lim.linear_deceleration,
            angular_acceleration=lim.angular_acceleration,
            angular_deceleration=lim.angular_deceleration,
            lidar_x=lidar.x,
            lidar_y=lidar.y,
            lidar_theta=lidar.theta,
            lidar_beams=lidar.beams,
            lidar_fov=lidar.fov,
            lidar_range=lidar.range_max,
            lidar_range_min=lidar.range_min,
            lidar_range_noise=lidar.noise,
            lidar_rate=lidar.rate,
            odom_translation_noise=odo.translation_noise,
            odom_rotation_noise=odo.rotation_noise,
            odom_translation_additive=odo.translation_additive,
            odom_rotation_additive=odo.rotation_additive,
            imu_rate=imu.rate,
            imu_yaw_rate_noise=imu.yaw_rate_noise,
            imu_yaw_rate_bias=imu.yaw_rate_bias,
            imu_acceleration_noise=imu.acceleration_noise,
            dock_distance_tolerance=self.charger.distance_tolerance,
            dock_heading_tolerance=self.charger.heading_tolerance,
            sign_camera_range=self.sign_camera.range if self.sign_camera is not None else 0.0,
            sign_camera_fov=self.sign_camera.fov if self.sign_camera is not None else 0.0,
            charger_plate_width=self.charger.plate_width,
            charger_notch_width=self.charger.notch_width,
            charger_notch_depth=self.charger.notch_depth,
        )

    def to_document(self) -> dict[str, Any]:
        """The profile in the file's shape: :func:`parse_profile` reads it back unchanged."""
        doc = self.to_dict()
        del doc["inscribed_radius"], doc["circumscribed_radius"]
        return doc

    def to_dict(self) -> dict[str, Any]:
        """The profile in the file's shape plus the body's radii (what ``GET /api/robot``
        shows)."""
        lidar = asdict(self.lidar)
        pose = {"x": lidar.pop("x"), "y": lidar.pop("y"), "theta": lidar.pop("theta")}
        return {
            "name": self.name,
            "description": self.description,
            "footprint": footprint_document(self.footprint),
            "inscribed_radius": self.inscribed_radius,
            "circumscribed_radius": self.circumscribed_radius,
            "limits": asdict(self.limits),
            "cruise": asdict(self.cruise),
            "lidar": {"pose": pose, **lidar},
            "odometry": asdict(self.odometry),
            "imu": asdict(self.imu),
            "charger": asdict(self.charger),
            "reverse": {"allowed": self.reverse.allowed, "rear_view": self.rear_view},
            **({"ros": asdict(self.ros)} if self.ros is not None else {}),
            **({"sign_camera": asdict(self.sign_camera)}
               if self.sign_camera is not None else {}),
            **({"payload": asdict(self.payload)} if self.payload is not None else {}),
        }


# -- loading ------------------------------------------------------------------------------------


def builtin_profiles() -> list[str]:
    """The names of the built-in profiles (``polynav/robot/profiles/*.yaml``)."""
    return sorted(p.stem for p in PROFILES_DIR.glob("*.yaml"))


def load_profile(ref: str | Path | None = None) -> RobotProfile:
    """A profile from a file path or a built-in name (``None``: the demo robot).

    Raises:
        ProfileError: no such file or built-in, unreadable, not YAML, or invalid (the field named).
    """
    if ref is None:
        ref = DEFAULT_PROFILE
    path = Path(ref)
    if not path.is_file():
        if isinstance(ref, str) and "/" not in ref and not ref.endswith((".yaml", ".yml")):
            path = PROFILES_DIR / f"{ref}.yaml"
            if not path.is_file():
                raise ProfileError("robot", f"no profile file or built-in {ref!r} (built-in: "
                                            f"{', '.join(builtin_profiles())})")
        else:
            raise ProfileError("robot", f"{ref}: no such file")
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise ProfileError("robot", f"{path}: cannot read: {exc}") from exc
    try:
        doc = safe_yaml.load(text)
    except yaml.YAMLError as exc:
        raise ProfileError("robot", f"{path}: not valid YAML: {exc}") from exc
    profile = parse_profile(doc)
    log.info("robot profile %r from %s", profile.name, path)
    return profile


def parse_profile(doc: object) -> RobotProfile:
    """A profile from its parsed YAML or JSON document (a mapping).

    Raises:
        ProfileError: a missing, unknown or invalid field; ``field`` names it.
    """
    top = _mapping(doc, "robot")
    _known(top, "robot", ("name", "description", "footprint", "limits", "cruise", "lidar",
                          "odometry", "imu", "charger", "reverse", "ros", "sign_camera",
                          "payload"))
    name = top.get("name")
    if not isinstance(name, str) or not name.strip():
        raise ProfileError("name", f"expected a non-empty string, got {name!r}")
    description = top.get("description", "")
    if not isinstance(description, str):
        raise ProfileError("description", f"expected a string, got {description!r}")
    if "footprint" not in top:
        raise ProfileError("footprint", "missing: give a radius or a polygon")
    lidar_doc = _mapping(top.get("lidar", {}), "lidar")
    lidar_fields = dict(lidar_doc)
    pose = lidar_fields.pop("pose", {})
    _known(lidar_fields, "lidar", ("range_min", "range_max", "fov", "beams", "rate", "noise"))
    pose_doc = _mapping(pose, "lidar.pose")
    _known(pose_doc, "lidar.pose", ("x", "y", "theta"))
    lidar = _section(LidarSpec, {**lidar_fields, **pose_doc}, "lidar",
                     aliases={"x": "pose.x", "y": "pose.y", "theta": "pose.theta"})
    return RobotProfile(
        name=name.strip(),
        description=description,
        footprint=_footprint(top["footprint"]),
        limits=_section(Limits, top.get("limits", {}), "limits"),
        cruise=_section(Cruise, top.get("cruise", {}), "cruise"),
        lidar=lidar,
        odometry=_section(OdometryNoise, top.get("odometry", {}), "odometry"),
        imu=_section(ImuSpec, top.get("imu", {}), "imu"),
        charger=_section(ChargerContact, top.get("charger", {}), "charger"),
        reverse=_reverse(top.get("reverse", {})),
        ros=_ros(top.get("ros")),
        sign_camera=(None if top.get("sign_camera") is None
                     else _section(SignCamera, top["sign_camera"], "sign_camera")),
        payload=(None if top.get("payload") is None
                 else _section(Payload, top["payload"], "payload")),
    )


def _ros(raw: object) -> BridgeConfig | None:
    if raw is None:
        return None
    try:
        return BridgeConfig.from_mapping(_mapping(raw, "ros"))
    except ConfigError as exc:
        raise ProfileError(exc.key, str(exc).split(": ", 1)[-1]) from exc


def _reverse(raw: object) -> Reverse:
    doc = _mapping(raw, "reverse")
    _known(doc, "reverse", ("allowed", "rear_view"))
    allowed = doc.get("allowed", True)
    if not isinstance(allowed, bool):
        raise ProfileError("reverse.allowed", f"expected true or false, got {allowed!r}")
    view = doc.get("rear_view")
    return Reverse(allowed, None if view is None else _number(view, "reverse.rear_view"))


def _footprint(raw: object) -> Footprint:
    doc = _mapping(raw, "footprint")
    _known(doc, "footprint", ("radius", "polygon"))
    if ("radius" in doc) == ("polygon" in doc):
        raise ProfileError("footprint", "give exactly one of radius or polygon")
    if "radius" in doc:
        radius = _number(doc["radius"], "footprint.radius")
        try:
            return Footprint.circle(radius, key="robot.footprint")
        except ConfigError as exc:
            raise ProfileError("footprint.radius", exc.reason) from None
    points = doc["polygon"]
    if not isinstance(points, list):
        raise ProfileError("footprint.polygon", f"expected a list of [x, y], got {points!r}")
    vertices = []
    for n, p in enumerate(points):
        key = f"footprint.polygon[{n}]"
        if not isinstance(p, list | tuple) or len(p) != 2:
            raise ProfileError(key, f"expected [x, y], got {p!r}")
        vertices.append((_number(p[0], key), _number(p[1], key)))
    try:
        footprint = Footprint.polygon(vertices, key="robot.footprint")
    except ConfigError as exc:
        raise ProfileError("footprint.polygon", exc.reason) from None
    if footprint.inscribed_radius < _MIN_INSCRIBED:
        raise ProfileError(
            "footprint.polygon",
            f"must hold the base origin with room about it (at least {_MIN_INSCRIBED:g} m to "
            "every edge): the origin is the robot's centre of rotation, inside its body",
        )
    return footprint


def _section(cls: type[Any], raw: object, key: str,
             aliases: dict[str, str] | None = None) -> Any:
    doc = _mapping(raw, key)
    names = [f for f in cls.__dataclass_fields__]
    aliases = aliases or {}
    _known(doc, key, names)
    values: dict[str, Any] = {}
    for name, value in doc.items():
        full = f"{key}.{aliases.get(name, name)}"
        if name == "beams":
            if isinstance(value, float) and value.is_integer():
                value = int(value)  # 108.0 is an integer in JSON Schema's sense
            if isinstance(value, bool) or not isinstance(value, int):
                raise ProfileError(full, f"expected an integer, got {value!r}")
            values[name] = value
        else:
            values[name] = _number(value, full)
    return cls(**values)


def _mapping(value: object, key: str) -> dict[str, Any]:
    if not isinstance(value, dict):
        raise ProfileError(key, f"expected a mapping, got {value!r}")
    for k in value:
        if not isinstance(k, str):
            raise ProfileError(key, f"keys must be strings, got {k!r}")
    return value


def _known(doc: dict[str, Any], key: str, names: tuple[str, ...] | list[str]) -> None:
    for k in doc:
        if k not in names:
            where = f"{key}.{k}" if key != "robot" else k
            raise ProfileError(where, f"unknown key (known: {', '.join(names)})")


def _number(value: object, key: str) -> float:
    # bool is an int subclass, and "radius: yes" is surely a mistake.
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise ProfileError(key, f"expected a finite number, got {value!r}")
    return float(value)


# -- validation ---------------------------------------------------------------------------------


def _validate(p: RobotProfile) -> None:
    lim = p.limits
    for name in ("max_linear_velocity", "max_angular_velocity", "linear_acceleration",
                 "linear_deceleration", "angular_acceleration", "angular_deceleration"):
        _positive(getattr(lim, name), f"limits.{name}")
    for name, limit in (("linear_velocity", "max_linear_velocity"),
                        ("angular_velocity", "max_angular_velocity"),
                        ("linear_acceleration", "linear_acceleration"),
                        ("linear_deceleration", "linear_deceleration"),
                        ("angular_acceleration", "angular_acceleration")):
        value = getattr(p.cruise, name)
        _positive(value, f"cruise.{name}")
        top = getattr(lim, limit)
        if value > top:
            raise ProfileError(f"cruise.{name}", f"{value:g} is above limits.{limit} ({top:g})")
    li = p.lidar
    if not p.footprint.contains_point(Pose2D(), li.x, li.y):
        raise ProfileError(
            "lidar.pose",
            f"({li.x:g}, {li.y:g}) is outside the footprint: the lidar is mounted on the base, "
            "in its frame (x forward, y left, origin at the centre of rotation)",
        )
    if not -math.pi <= li.theta <= math.pi:
        raise ProfileError("lidar.pose.theta", f"must be within [-π, π], got {li.theta:g}")
    _non_negative(li.range_min, "lidar.range_min")
    _positive(li.range_max, "lidar.range_max")
    if not li.range_min < li.range_max:
        raise ProfileError("lidar.range_min", f"must be below lidar.range_max ({li.range_max:g})")
    if not 0.0 < li.fov <= 2.0 * math.pi + 1e-9:
        raise ProfileError("lidar.fov", f"must be within (0, 2π], got {li.fov:g}")
    if isinstance(li.beams, bool) or not isinstance(li.beams, int) or li.beams < 1:
        raise ProfileError("lidar.beams", f"must be an integer >= 1, got {li.beams!r}")
    _positive(li.rate, "lidar.rate")
    _non_negative(li.noise, "lidar.noise")
    for name in ("translation_noise", "rotation_noise", "translation_additive",
                 "rotation_additive"):
        _non_negative(getattr(p.odometry, name), f"odometry.{name}")
    _positive(p.imu.rate, "imu.rate")
    for name in ("yaw_rate_noise", "yaw_rate_bias", "acceleration_noise"):
        _non_negative(getattr(p.imu, name), f"imu.{name}")
    for name in ("distance_tolerance", "heading_tolerance", "plate_width", "notch_width",
                 "notch_depth"):
        _positive(getattr(p.charger, name), f"charger.{name}")
    if not p.charger.notch_width < p.charger.plate_width:
        raise ProfileError("charger.notch_width",
                           f"must be below charger.plate_width ({p.charger.plate_width:g})")
    if p.reverse.rear_view is not None:
        _non_negative(p.reverse.rear_view, "reverse.rear_view")
    if p.sign_camera is not None:
        _positive(p.sign_camera.range, "sign_camera.range")
        if not 0.0 < p.sign_camera.fov <= 2.0 * math.pi + 1e-9:
            raise ProfileError("sign_camera.fov",
                               f"must be within (0, 2π], got {p.sign_camera.fov:g}")
    if p.payload is not None:
        _non_negative(p.payload.max_mass, "payload.max_mass")
        for name in ("linear_velocity", "angular_velocity", "linear_acceleration"):
            value = getattr(p.payload, name)
            _positive(value, f"payload.{name}")
            top = getattr(p.cruise, name)
            if value > top:
                raise ProfileError(f"payload.{name}", f"{value:g} is above cruise.{name} "
                                                      f"({top:g})")
    physics = SimConfig().physics_rate
    for key, rate in (("lidar.rate", li.rate), ("imu.rate", p.imu.rate)):
        if rate > physics:
            raise ProfileError(key, f"must be <= {physics:g} Hz (the simulator's physics rate)")


def _positive(value: float, key: str) -> None:
    if not (math.isfinite(value) and value > 0.0):
        raise ProfileError(key, f"must be > 0, got {value:g}")


def _non_negative(value: float, key: str) -> None:
    if not (math.isfinite(value) and value >= 0.0):
        raise ProfileError(key, f"must be >= 0, got {value:g}")
