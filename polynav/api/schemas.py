"""The native API's JSON bodies (pydantic), converted to and from domain values at once.

Pydantic lives only here, at the edge (STYLE R6): routes call ``to_domain()`` on what comes in and
``from_domain()`` on what goes out.
"""

from __future__ import annotations

import logging
import math
from typing import Annotated, Any, Literal

from pydantic import (
    AfterValidator,
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Field,
    StrictBool,
    model_validator,
)
from typing_extensions import TypedDict

from polynav.api.schemas_doors import StatusDoorsOut
from polynav.api.schemas_mapping import MappingStatusOut
from polynav.geometry import Pose2D
from polynav.nav.attempt import PRECISE_POSITION_UNCERTAINTY, GoalOptions
from polynav.runtime.goal_commands import GoalFrame
from polynav.runtime.settings import SETTING_RANGES
from polynav.site import Point, PointKind

log = logging.getLogger(__name__)

# Integers are stored in SQLite, whose INTEGER is a signed 64-bit value: a larger one was not a
# 422 but an OverflowError deep in the store. The bound is the I-JSON one (RFC 7493 §2.2), well
# inside int64: a JSON number above 2**53 may reach a client (or a JSON Schema validator) as a
# rounded double, and then a value the server refuses could look as if it met the maximum.
MAX_INTEGER = 2**53 - 1
MAX_NAME = 200
MAX_COORDINATE = 1.0e6  # [m] no site is a thousand kilometres wide; keeps poses far from overflow
MAX_HEADING = 2.0 * math.pi  # [rad] one turn either way; the server wraps into (-pi, pi]
MAX_LOCAL_ROTATION = 4.0 * math.pi  # [rad] the runtime's bound on a local move
MAX_LOCAL_DISTANCE = 10.0  # [m] likewise

# A name is what the site store accepts (non-empty, at most 200 characters, no control character,
# no leading or trailing white space as ``str.strip`` sees it) and what a URL path segment can
# carry back to us: no "/", and not "." or ".." (clients fold those away). C1 controls and lone
# surrogates are refused too: they cannot be written to SQLite as UTF-8.
_CONTROL = "\\u0000-\\u001f\\u007f-\\u009f"
_SPACE = " \\u00a0\\u1680\\u2000-\\u200a\\u2028\\u2029\\u202f\\u205f\\u3000"
NAME_PATTERN = f"^[^{_CONTROL}{_SPACE}/](?:[^{_CONTROL}/]*[^{_CONTROL}{_SPACE}/])?$"
NAME_DESCRIPTION = (
    f"1 to {MAX_NAME} characters; no control character, no '/', no leading or trailing white "
    "space; not '.' or '..'"
)
_DOT_SEGMENTS = (".", "..")


def _not_a_dot_segment(name: str) -> str:
    if name in _DOT_SEGMENTS:
        raise ValueError("'.' and '..' are path segments, not names")
    return name


Name = Annotated[
    str,
    Field(
        min_length=1,
        max_length=MAX_NAME,
        pattern=NAME_PATTERN,
        description=NAME_DESCRIPTION,
        json_schema_extra={"not": {"enum": list(_DOT_SEGMENTS)}},
    ),
    AfterValidator(_not_a_dot_segment),
]
# Numbers are strict: JSON "1.5" (a string) is not a number, as the document says.
Finite = Annotated[float, Field(strict=True, allow_inf_nan=False)]
Coordinate = Annotated[
    float, Field(strict=True, allow_inf_nan=False, ge=-MAX_COORDINATE, le=MAX_COORDINATE)
]
Heading = Annotated[float, Field(strict=True, allow_inf_nan=False, ge=-MAX_HEADING, le=MAX_HEADING)]


def _integral(value: Any) -> Any:
    # JSON Schema counts 12.0 as an integer; strict mode would not, and would refuse "12" too.
    if isinstance(value, float) and value.is_integer():
        return int(value)
    return value


Integer = Annotated[
    int, Field(strict=True, ge=-MAX_INTEGER, le=MAX_INTEGER), BeforeValidator(_integral)
]
KindName = Literal[
    "general", "charger", "initial", "front-desk", "lift-outside", "lift-inside", "gate", "custom"
]


def _alternatives(*branches: tuple[tuple[str, ...], tuple[str, ...]]) -> dict[str, Any]:
    """JSON Schema for "one of these field sets": each branch is (fields that must be numbers or
    strings, fields that must be absent or null). The model validators enforce the same."""
    any_of = []
    for present, absent in branches:
        props: dict[str, Any] = {name: {"not": {"type": "null"}} for name in present}
        props.update({name: {"type": "null"} for name in absent})
        any_of.append({"required": list(present), "properties": props} if present
                      else {"properties": props})
    return {"anyOf": any_of}


class _Body(BaseModel):
    model_config = ConfigDict(extra="forbid")


class PoseOut(BaseModel):
    x: float
    y: float
    theta: float

    @classmethod
    def from_domain(cls, pose: Pose2D) -> PoseOut:
        return cls(x=pose.x, y=pose.y, theta=pose.theta)


class PoseIn(_Body):
    """A pose in the map frame: position [m], heading [rad]."""

    x: Coordinate
    y: Coordinate
    theta: Heading = 0.0

    def to_domain(self) -> Pose2D:
        return Pose2D(self.x, self.y, self.theta)


class Ok(BaseModel):
    """A command was accepted."""

    ok: bool = True


# --- status -----------------------------------------------------------------------------------


class VelocityOut(BaseModel):
    linear: float
    angular: float


class BatteryOut(BaseModel):
    percent: float
    charging: bool


class EStopOut(BaseModel):
    hardware: bool
    software: bool


class UncertaintyOut(BaseModel):
    """One standard deviation of the pose's error: ``position`` [m] along its worst-known
    direction, ``heading`` [rad]."""

    position: float
    heading: float


class LocalizationOut(BaseModel):
    state: str
    quality: float | None
    uncertainty: UncertaintyOut | None = Field(
        default=None, description="how well the pose is known; null when the localizer "
                                  "does not say")


class GoalOut(BaseModel):
    x: float
    y: float
    theta: float
    point: str | None


class RouteLegOut(BaseModel):
    """One leg of a route across maps: ``drive`` (to ``goal`` on ``map``), ``lift`` (car from
    floor to floor) or ``switch`` (a direct connection)."""

    kind: Literal["drive", "lift", "switch"]
    map: str | None = None
    point: str | None = None
    goal: PoseOut | None = None
    car: str | None = None
    from_floor: str | None = None
    from_map: str | None = None
    to_floor: str | None = None
    to_map: str | None = None


class RouteLiftOut(BaseModel):
    """The lift sequence now: the car, the phase (``going_to_lift``, ``waiting_for_session``,
    ``calling``, ``waiting_for_car``, ``entering``, ``riding``, ``switching_map``,
    ``exiting``, ``left``), the floors, and the manoeuvre under way after a blocked door
    (``avoiding``: out of the car's way after a blocked entry; ``backing_in``: back into the
    car after a blocked exit)."""

    car: str
    phase: str
    from_floor: str
    to_floor: str
    manoeuvre: Literal["avoiding", "backing_in"] | None = None


class RouteOut(BaseModel):
    """A goal on another map: its legs, the one running, the lift phase, cars given up."""

    goal_map: str
    legs: list[RouteLegOut]
    current_leg: int
    lift: RouteLiftOut | None
    excluded_cars: list[str]


class NavigationOut(BaseModel):
    state: Literal["idle", "running", "paused", "succeeded", "failed", "canceled"]
    goal: GoalOut | None
    reason: str | None
    distance_remaining: float | None
    phase: Literal["leave_charger", "navigate", "dock"] | None
    retries: int
    arrival_uncertainty: UncertaintyOut | None = Field(
        default=None, description="the localization's uncertainty when the robot arrived")
    route: RouteOut | None = Field(default=None,
                                   description="present while (or after) a goal on another map")


class StatusOut(BaseModel):
    """GET /api/status: the runtime's snapshot, refreshed on the robot's clock."""

    mode: Literal["free", "mapping", "navigating", "busy"]
    map: str | None
    floor: str | None
    floor_level: int | None = Field(description="the floor's level in the site, if it has one")
    pose: PoseOut
    frame: Literal["map", "odom"] = Field(
        description="the frame of `pose` and of the navigation goal: `map` (on a map: `map` "
        "while navigating, the map being built while mapping, the floor's map otherwise) or "
        "`odom` (navigating without a map: the odometry frame, (0, 0, 0) where the robot was "
        "switched on)"
    )
    velocity: VelocityOut
    battery: BatteryOut
    estop: EStopOut
    localization: LocalizationOut
    navigation: NavigationOut
    mapping: MappingStatusOut | None = Field(
        description="the mapping session while mapping, or while a stop job saves the map"
    )
    stamp: float
    doors: StatusDoorsOut | None = Field(
        default=None,
        description="the door the robot waits at, those it passes, and its floor's doors' states",
    )
    load: dict[str, str | float] | None = Field(
        default=None, description="the cart or cabin the robot carries: its `name`, `kind` "
        "(`cart` or `cabin`) and `mass` [kg]; left out when it carries nothing")
    links: dict[str, str] = Field(
        default_factory=dict,
        description="serial lines the dialects serve, name -> device path (`galileo_serial`: "
        "the serial device or pseudo-terminal a Galileo host opens)",
    )


class RelocalizedOut(BaseModel):
    """Where relocalization found the robot, and how well its scan fits there."""

    x: float
    y: float
    theta: float
    score: float = Field(ge=0.0, le=1.0, description="mean likelihood of the scan's endpoints")


# --- maps and points --------------------------------------------------------------------------


class MapOut(BaseModel):
    name: str
    floor: str | None
    resolution: float = Field(description="cell size [m]")
    width: int = Field(description="cells along x")
    height: int = Field(description="cells along y")
    origin: PoseOut = Field(description="pose of the bottom-left cell's corner")

    @classmethod
    def from_domain(cls, record: Any) -> MapOut:
        return cls(
            name=record.name,
            floor=record.floor,
            resolution=record.resolution,
            width=record.width,
            height=record.height,
            origin=PoseOut.from_domain(record.origin),
        )


class GridOut(BaseModel):
    """An occupancy grid: ``data`` row by row from the bottom row, 100 / 0 / -1."""

    resolution: float = Field(description="cell size [m]")
    width: int
    height: int
    origin: PoseOut = Field(description="pose of the bottom-left cell's corner")
    data: list[int] = Field(description="width x height values, bottom row first")

    @classmethod
    def from_domain(cls, grid: Any) -> GridOut:
        info = grid.info
        return cls(resolution=info.resolution, width=info.width, height=info.height,
                   origin=PoseOut.from_domain(info.origin), data=grid.data.ravel().tolist())


class MappingStartIn(_Body):
    """Start mapping: a new map (no body, or no ``map``), or update (extend) ``map``, the robot
    localized on it at ``point``, at the pose, by its navigation estimate when navigating on
    it, or else by global relocalization."""

    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra=_alternatives(
            ((), ("x", "y", "theta", "point")),
            (("map", "x", "y"), ("point",)),
            (("map", "point"), ("x", "y", "theta")),
        ),
    )

    map: Name | None = None
    point: Name | None = None
    x: Coordinate | None = None
    y: Coordinate | None = None
    theta: Heading | None = None

    @model_validator(mode="after")
    def _one_origin(self) -> MappingStartIn:
        pose = _pose_or_none(self.x, self.y, self.theta)
        if pose is not None and self.point is not None:
            raise ValueError("give a point or a pose, not both")
        if (pose is not None or self.point is not None) and self.map is None:
            raise ValueError("a point or pose locates the robot on the map being updated: "
                             "name the map")
        return self

    def pose(self) -> Pose2D | None:
        return _pose_or_none(self.x, self.y, self.theta)


class MapSaveIn(_Body):
    """Where to save the map being built."""

    name: Name
    overwrite: StrictBool = False


class PointOut(BaseModel):
    name: str
    map: str
    floor: str | None
    x: float
    y: float
    theta: float
    kind: KindName
    number: int | None = None

    @classmethod
    def from_domain(cls, point: Point, floor: str | None) -> PointOut:
        return cls(
            name=point.name,
            map=point.map_name,
            floor=floor,
            x=point.pose.x,
            y=point.pose.y,
            theta=point.pose.theta,
            kind=point.kind.value,
            number=point.number,
        )


class PointIn(_Body):
    """A new named point on a map."""

    name: Name
    map: Name
    x: Coordinate
    y: Coordinate
    theta: Heading = 0.0
    kind: KindName = "general"
    number: Integer | None = None

    def to_domain(self) -> Point:
        return Point(
            self.name, self.map, Pose2D(self.x, self.y, self.theta), PointKind(self.kind),
            self.number,
        )


class PointUpdate(_Body):
    """A change of a point: the fields given replace the old ones (``name`` renames it)."""

    name: Name | None = None
    x: Coordinate | None = None
    y: Coordinate | None = None
    theta: Heading | None = None
    kind: KindName | None = None
    number: Integer | None = None

    def to_domain(self, old: Point) -> Point:
        pose = old.pose
        return Point(
            self.name if self.name is not None else old.name,
            old.map_name,
            Pose2D(
                self.x if self.x is not None else pose.x,
                self.y if self.y is not None else pose.y,
                self.theta if self.theta is not None else pose.theta,
            ),
            PointKind(self.kind) if self.kind is not None else old.kind,
            self.number if "number" in self.model_fields_set else old.number,
        )


# --- navigation -------------------------------------------------------------------------------


def _pose_or_none(x: float | None, y: float | None, theta: float | None) -> Pose2D | None:
    if x is None and y is None and theta is None:
        return None
    if x is None or y is None:
        raise ValueError("a pose needs both x and y")
    return Pose2D(x, y, theta if theta is not None else 0.0)


class NavigationStartIn(_Body):
    """Start navigating on a map, localized at a named point, a pose, or where the robot is."""

    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra=_alternatives(((), ("x", "y", "theta")), (("x", "y"), ("point",))),
    )

    map: Name
    point: Name | None = None
    x: Coordinate | None = None
    y: Coordinate | None = None
    theta: Heading | None = None

    @model_validator(mode="after")
    def _one_origin(self) -> NavigationStartIn:
        pose = _pose_or_none(self.x, self.y, self.theta)
        if pose is not None and self.point is not None:
            raise ValueError("give a point or a pose, not both")
        return self

    def pose(self) -> Pose2D | None:
        return _pose_or_none(self.x, self.y, self.theta)


class GoalIn(_Body):
    """A navigation goal: a named point, or a pose (on the current map unless ``map`` is set),
    in the current frame unless ``frame`` says otherwise."""

    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra=_alternatives(
            (("point",), ("x", "y", "theta", "frame")), (("x", "y"), ("point",))
        ),
    )

    point: Name | None = None
    x: Coordinate | None = None
    y: Coordinate | None = None
    theta: Heading | None = None
    map: Name | None = None
    precise: StrictBool = Field(
        default=False,
        description="arrive only where localization knows the pose to "
                    f"{PRECISE_POSITION_UNCERTAINTY} m; else fail 'not localized'")
    max_position_uncertainty: float | None = Field(
        default=None, gt=0.0, le=10.0, allow_inf_nan=False, strict=True,
        description="the same with its own limit [m] (one standard deviation)")
    frame: Literal["map", "odom", "robot"] | None = Field(
        default=None,
        description="the frame of the pose: the current one (the status's `frame`: `map`, or "
        "`odom` without a map; the default; 409 if another is named), or `robot`: relative to "
        "where the robot stands now, x ahead, y to the left, theta from its heading "
        '(`{"x": 10, "y": 0, "theta": 0, "frame": "robot"}` is 10 m ahead)',
    )

    @model_validator(mode="after")
    def _point_or_pose(self) -> GoalIn:
        pose = _pose_or_none(self.x, self.y, self.theta)
        if (pose is None) == (self.point is None):
            raise ValueError("give either a point or x and y")
        if self.frame is not None and self.point is not None:
            raise ValueError("a point is named on its map: give a frame with a pose only")
        return self

    def pose(self) -> Pose2D | None:
        return _pose_or_none(self.x, self.y, self.theta)

    def options(self) -> GoalOptions | None:
        """The goal's options, or ``None`` for the defaults (a precise arrival, if asked)."""
        limit = self.max_position_uncertainty
        if limit is None and self.precise:
            limit = PRECISE_POSITION_UNCERTAINTY
        return None if limit is None else GoalOptions(max_position_uncertainty=limit)

    def goal_frame(self) -> GoalFrame | None:
        return None if self.frame is None else GoalFrame(self.frame)


class GoalAccepted(BaseModel):
    """A goal was accepted; ``id`` names its navigation attempt in events."""

    id: int


# --- control ----------------------------------------------------------------------------------


class TeleopIn(_Body):
    """A velocity command [m/s, rad/s], clamped to the settings; repeat it within the dead-man
    timeout or the base stops."""

    linear: Finite = Field(description="[m/s], clamped to max_linear_velocity")
    angular: Finite = Field(0.0, description="[rad/s], clamped to max_angular_velocity")


class EStopIn(_Body):
    """The software emergency stop (the hardware button is separate)."""

    on: StrictBool


class LocalMoveIn(_Body):
    """Rotate by an angle [rad] or drive straight a distance [m] (negative: backwards)."""

    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra=_alternatives(
            (("rotate",), ("distance",)), (("distance",), ("rotate",))
        ),
    )

    rotate: Annotated[
        float,
        Field(strict=True, allow_inf_nan=False, ge=-MAX_LOCAL_ROTATION, le=MAX_LOCAL_ROTATION),
    ] | None = None
    distance: Annotated[
        float,
        Field(strict=True, allow_inf_nan=False, ge=-MAX_LOCAL_DISTANCE, le=MAX_LOCAL_DISTANCE),
    ] | None = None

    @model_validator(mode="after")
    def _exactly_one(self) -> LocalMoveIn:
        if (self.rotate is None) == (self.distance is None):
            raise ValueError("give exactly one of rotate or distance")
        return self


# --- settings ---------------------------------------------------------------------------------


def _setting(key: str) -> Any:
    lo, hi = SETTING_RANGES[key]
    return Annotated[float, Field(strict=True, allow_inf_nan=False, ge=lo, le=hi)]


# Built from the runtime's table so a new setting and its range reach the document by themselves.
# A TypedDict (not a model) so that a field is either absent or a number, never null.
SettingsIn = TypedDict(  # type: ignore[misc]
    "SettingsIn", {key: _setting(key) for key in SETTING_RANGES}, total=False
)
SettingsIn.__doc__ = (
    "Settings to change (SI units), each within its range; all or none apply. A change that "
    "contradicts the values it is combined with (obstacle_stop_distance above "
    "obstacle_slowdown_distance, critical_battery_percent above low_battery_percent, the LED "
    "colour all 0) is refused with 409."
)
SettingsIn.__pydantic_config__ = ConfigDict(extra="forbid")  # type: ignore[attr-defined]
SettingsOut = TypedDict(  # type: ignore[misc]
    "SettingsOut", {key: _setting(key) for key in SETTING_RANGES}
)
SettingsOut.__doc__ = "Every setting with its current value (SI units)."


class FleetRobotOut(BaseModel):
    """One robot of the building, as the fleet knows it (GET /api/fleet)."""

    robot_id: str = Field(description="the robot's id in the fleet (VDA 5050 serialNumber)")
    ports: dict[str, int] = Field(description="where the robot listens: native API and dialects")
    floor: str | None
    map: str | None
    pose: PoseOut | None
    mode: str
    navigation_state: str
    order_id: str = Field(description="the robot's current or last fleet order, '' if none")
    order_state: Literal["none", "running", "succeeded", "failed"]
    waiting_for: str | None = Field(description="the traffic zone the robot waits for, if any")
    zones: list[str] = Field(description="the traffic zones the robot holds")
    battery_percent: float
    errors: list[str]


class FleetOut(BaseModel):
    """GET /api/fleet: every robot in the building (one, for a lone robot)."""

    robots: list[FleetRobotOut]
