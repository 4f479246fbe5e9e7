"""Robot settings: the handful of values an operator may change at run time, with their ranges.

These are the settings every vendor dialect exposes in some form (max speeds, goal tolerances,
robot radius, obstacle distances, battery thresholds). :class:`RobotSettings` is a frozen value;
:meth:`RobotSettings.apply` validates a partial update from outside and returns a new value, or
raises :class:`~polynav.errors.InvalidRequest` naming the field (the native API answers 422). The
runtime persists the values through the site store and turns them into the navigation stack's
configs with :meth:`RobotSettings.stack_config` (a live update replaces whole configs between
ticks, STYLE R10).

Ranges (inclusive, SI units):

==========================  ===========  =======
setting                     range        default
==========================  ===========  =======
max_linear_velocity         0.1 .. 3.0   0.6 m/s (at most the robot profile's limit)
max_angular_velocity        0.2 .. 6.0   1.5 rad/s (at most the robot profile's limit)
xy_goal_tolerance           0.01 .. 0.25 0.05 m (below the controller's 0.3 m lookahead)
yaw_goal_tolerance          0.01 .. 1.0  0.05 rad
robot_radius                0.1 .. 0.6   0.25 m (the planning footprint; inflation follows;
                                         at least the profile body's inscribed radius)
obstacle_slowdown_distance  0.2 .. 5.0   1.5 m
obstacle_stop_distance      0.05 .. 2.0  0.35 m (at most obstacle_slowdown_distance)
low_battery_percent         1 .. 90      20 %
critical_battery_percent    0 .. 50      10 % (at most low_battery_percent)
full_battery_percent        50 .. 100    95 % (auto-charge charges to it; above low_battery)
auto_charge                 0 .. 1       1 (1: below low_battery_percent the robot docks,
                                         charges to full_battery_percent and goes on)
led_luminance               0 .. 100     100 % (the light strip's brightness)
led_red, led_green, led_blue  0 .. 100   0, 100, 0 % (its colour; not all 0)
social_distance             0.3 .. 3.0   0.8 m (kept from people where there is room)
people_patience             1 .. 600     60 s (waiting for people to make way, then fail)
==========================  ===========  =======

The defaults are the demo robot's; :meth:`RobotSettings.defaults_for` gives another robot's
(its profile's cruise speeds and inscribed radius). Given the robot's profile, :meth:`apply`
also refuses speeds above the profile's limits and a planning footprint smaller than the body
(:class:`BeyondProfile`, a 422 over the native API: the document's ranges are the same for every
robot, the profile's are narrower), since a planner that believes the robot thinner than it is
steers it into walls.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass, fields, replace

from polynav.errors import ConfigError, InvalidRequest
from polynav.maps.costmap import CostmapConfig
from polynav.nav.stack import StackConfig
from polynav.robot.profile import RobotProfile

log = logging.getLogger(__name__)


class BeyondProfile(ConfigError, InvalidRequest):
    """A setting the robot's profile forbids: a speed above its limits, a planning footprint
    below its body. ``field`` (and ``key``) is the setting's name.

    A :class:`ConfigError` first (the native API's 422 ``invalid_setting``), and an
    :class:`InvalidRequest` for the dialects that map only those (an invalid request, as an
    out-of-range value is)."""

    def __init__(self, field: str, reason: str) -> None:
        Exception.__init__(self, f"{field}: {reason}")
        self.key = self.field = field
        self.reason = reason

SETTING_RANGES: dict[str, tuple[float, float]] = {
    "max_linear_velocity": (0.1, 3.0),
    "max_angular_velocity": (0.2, 6.0),
    "xy_goal_tolerance": (0.01, 0.25),
    "yaw_goal_tolerance": (0.01, 1.0),
    "robot_radius": (0.1, 0.6),
    "obstacle_slowdown_distance": (0.2, 5.0),
    "obstacle_stop_distance": (0.05, 2.0),
    "low_battery_percent": (1.0, 90.0),
    "critical_battery_percent": (0.0, 50.0),
    "full_battery_percent": (50.0, 100.0),
    "auto_charge": (0.0, 1.0),
    "led_luminance": (0.0, 100.0),
    "led_red": (0.0, 100.0),
    "led_green": (0.0, 100.0),
    "led_blue": (0.0, 100.0),
    "social_distance": (0.3, 3.0),
    "people_patience": (1.0, 600.0),
}

# Obstacles raise costs this far [m] beyond the robot's radius, so paths keep off walls.
_INFLATION_MARGIN = 0.3


@dataclass(frozen=True, slots=True)
class RobotSettings:
    """Operator settings; see the module's table for units and ranges."""

    max_linear_velocity: float = 0.6
    max_angular_velocity: float = 1.5
    xy_goal_tolerance: float = 0.05
    yaw_goal_tolerance: float = 0.05
    robot_radius: float = 0.25
    obstacle_slowdown_distance: float = 1.5
    obstacle_stop_distance: float = 0.35
    low_battery_percent: float = 20.0
    critical_battery_percent: float = 10.0
    full_battery_percent: float = 95.0
    auto_charge: float = 1.0
    led_luminance: float = 100.0
    led_red: float = 0.0
    led_green: float = 100.0
    led_blue: float = 0.0
    social_distance: float = 0.8
    people_patience: float = 60.0

    def __post_init__(self) -> None:
        try:
            _validate(self)
        except InvalidRequest as exc:
            raise ConfigError(f"runtime.settings.{exc.field}", exc.reason) from exc

    @classmethod
    def defaults_for(cls, profile: RobotProfile) -> RobotSettings:
        """The default settings of ``profile``'s robot: its cruise speeds, and its inscribed
        radius as the planning footprint (within the settings' ranges)."""
        lo, hi = SETTING_RANGES["robot_radius"]
        return replace(
            cls(),
            max_linear_velocity=profile.cruise.linear_velocity,
            max_angular_velocity=profile.cruise.angular_velocity,
            robot_radius=min(hi, max(lo, profile.inscribed_radius)),
        )

    def apply(
        self, changes: Mapping[str, object], profile: RobotProfile | None = None
    ) -> RobotSettings:
        """These settings with ``changes`` applied, all validated before any takes effect.

        Args:
            changes: setting name to new value (numbers; booleans and strings are refused).
            profile: the robot's profile, whose limits and body bound the result.

        Returns:
            The new settings (``self`` is unchanged).

        Raises:
            InvalidRequest: an unknown name, a value that is not a finite number, a value out
                of its range, or a combination that contradicts itself; ``field`` names it.
            BeyondProfile: a speed above ``profile``'s limits or a planning footprint below
                its body (only the changed settings are held to it).
        """
        values: dict[str, float] = {}
        for key, value in changes.items():
            if key not in SETTING_RANGES:
                raise InvalidRequest(str(key), "unknown setting")
            values[key] = _number(key, value)
        candidate = asdict(self) | values
        new = _unchecked(candidate)
        _validate(new)
        if profile is not None:
            check_profile(new, profile, only=tuple(values))
        return new

    def to_dict(self) -> dict[str, float]:
        return {f.name: float(getattr(self, f.name)) for f in fields(self)}

    @classmethod
    def from_stored(
        cls, stored: Mapping[str, object], profile: RobotProfile | None = None
    ) -> RobotSettings:
        """Settings from the site store, skipping (with a warning) what no longer validates.

        A stored value that an older or newer polynav wrote, or that another robot's profile
        allowed, must not stop the robot from starting, so unknown keys and invalid values fall
        back to the defaults (``profile``'s when given).
        """
        settings = cls() if profile is None else cls.defaults_for(profile)
        for key, value in stored.items():
            if key not in SETTING_RANGES:
                log.warning("ignoring unknown stored setting %r", key)
                continue
            try:
                settings = settings.apply({key: value}, profile)
            except (InvalidRequest, ConfigError) as exc:
                log.warning("ignoring stored setting %s", exc)
        return settings

    def stack_config(self, base: StackConfig | None = None) -> StackConfig:
        """``base`` (default: the defaults) with these settings written into its components."""
        base = base or StackConfig()
        ctl = base.controller
        controller = replace(
            ctl,
            max_linear_velocity=self.max_linear_velocity,
            max_angular_velocity=self.max_angular_velocity,
            min_regulated_speed=min(ctl.min_regulated_speed, self.max_linear_velocity),
            min_approach_velocity=min(ctl.min_approach_velocity, self.max_linear_velocity),
            min_rotation_speed=min(ctl.min_rotation_speed, self.max_angular_velocity),
            xy_goal_tolerance=self.xy_goal_tolerance,
            yaw_goal_tolerance=self.yaw_goal_tolerance,
            slowdown_distance=self.obstacle_slowdown_distance,
            min_stop_distance=self.obstacle_stop_distance,
        )
        cm = base.costmap
        costmap: CostmapConfig = replace(
            cm,
            robot_radius=self.robot_radius,
            inflation_radius=max(cm.inflation_radius, self.robot_radius + _INFLATION_MARGIN),
        )
        people = replace(
            base.people, social_distance=self.social_distance, patience=self.people_patience
        )
        return replace(base, controller=controller, costmap=costmap, people=people)


_PROFILE_SPEEDS = {
    "max_linear_velocity": ("max_linear_velocity", "m/s"),
    "max_angular_velocity": ("max_angular_velocity", "rad/s"),
}


def check_profile(
    settings: RobotSettings, profile: RobotProfile, *, only: tuple[str, ...] | None = None
) -> None:
    """Refuse settings ``profile``'s robot cannot honour (see :class:`BeyondProfile`).

    Args:
        only: check just these settings (the ones a request changes); ``None`` checks all.

    Raises:
        BeyondProfile: naming the first setting at fault and the profile's bound.
    """
    def wanted(key: str) -> bool:
        return only is None or key in only

    for key, (limit, unit) in _PROFILE_SPEEDS.items():
        top = getattr(profile.limits, limit)
        value = getattr(settings, key)
        if wanted(key) and value > top + 1e-9:
            raise BeyondProfile(
                key, f"{value:g} {unit} is above the robot profile {profile.name!r}'s "
                     f"limits.{limit} ({top:g} {unit})",
            )
    body = profile.inscribed_radius
    if wanted("robot_radius") and settings.robot_radius < body - 1e-9:
        raise BeyondProfile(
            "robot_radius",
            f"{settings.robot_radius:g} m is below the body of robot profile {profile.name!r} "
            f"(inscribed radius {body:g} m): a planner that thinks the robot thinner than it "
            "is steers it into walls",
        )


def _unchecked(values: Mapping[str, float]) -> RobotSettings:
    """Build without ``__post_init__`` so that :meth:`RobotSettings.apply` raises the request
    error (a 422) rather than the config error a bad default would be."""
    new = object.__new__(RobotSettings)
    for key, value in values.items():
        object.__setattr__(new, key, value)
    return new


def _number(key: str, value: object) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise InvalidRequest(key, f"must be a number, got {type(value).__name__}")
    number = float(value)
    if not math.isfinite(number):
        raise InvalidRequest(key, f"must be finite, got {number}")
    return number


def _validate(settings: RobotSettings) -> None:
    for key, (lo, hi) in SETTING_RANGES.items():
        value = getattr(settings, key)
        if not lo <= value <= hi:
            raise InvalidRequest(key, f"must be within [{lo:g}, {hi:g}], got {value:g}")
    if settings.obstacle_stop_distance > settings.obstacle_slowdown_distance:
        raise InvalidRequest(
            "obstacle_stop_distance",
            f"must be <= obstacle_slowdown_distance ({settings.obstacle_slowdown_distance:g})",
        )
    if settings.critical_battery_percent > settings.low_battery_percent:
        raise InvalidRequest(
            "critical_battery_percent",
            f"must be <= low_battery_percent ({settings.low_battery_percent:g})",
        )
    if settings.full_battery_percent <= settings.low_battery_percent:
        raise InvalidRequest(
            "full_battery_percent",
            f"must be above low_battery_percent ({settings.low_battery_percent:g})",
        )
    if settings.auto_charge not in (0.0, 1.0):
        raise InvalidRequest(
            "auto_charge", f"must be 0 (off) or 1 (on), got {settings.auto_charge:g}"
        )
    if settings.led_red == settings.led_green == settings.led_blue == 0.0:
        raise InvalidRequest("led", "red, green and blue all 0 would be no colour")
