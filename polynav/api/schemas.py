"""The native API's JSON bodies (pydantic), converted to and from domain values at once.

Pydantic lives only here, at the edge (STYLE R6): routes call ``to_domain()`` on what comes in and
``from_domain()`` on what goes out.
"""

from __future__ import annotations

import logging
from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator

from polynav.geometry import Pose2D
from polynav.site import Point, PointKind

log = logging.getLogger(__name__)

Finite = Annotated[float, Field(allow_inf_nan=False)]
Name = Annotated[str, Field(min_length=1, max_length=200)]
KindName = Literal["general", "charger", "initial", "lift-outside", "lift-inside", "gate", "custom"]


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

    x: Finite
    y: Finite
    theta: Finite = 0.0

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


class LocalizationOut(BaseModel):
    state: str
    quality: float | None


class GoalOut(BaseModel):
    x: float
    y: float
    theta: float
    point: str | None


class NavigationOut(BaseModel):
    state: Literal["idle", "running", "paused", "succeeded", "failed", "canceled"]
    goal: GoalOut | None
    reason: str | None
    distance_remaining: float | None
    phase: Literal["leave_charger", "navigate", "dock"] | None
    retries: int


class StatusOut(BaseModel):
    """GET /api/status: the runtime's snapshot, refreshed on the robot's clock."""

    mode: Literal["free", "mapping", "navigating", "busy"]
    map: str | None
    floor: str | None
    pose: PoseOut
    velocity: VelocityOut
    battery: BatteryOut
    estop: EStopOut
    localization: LocalizationOut
    navigation: NavigationOut
    stamp: float


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
            kind=point.kind.value,  # type: ignore[arg-type]
            number=point.number,
        )


class PointIn(_Body):
    """A new named point on a map."""

    name: Name
    map: Name
    x: Finite
    y: Finite
    theta: Finite = 0.0
    kind: KindName = "general"
    number: int | None = None

    def to_domain(self) -> Point:
        return Point(
            self.name, self.map, Pose2D(self.x, self.y, self.theta), PointKind(self.kind),
            self.number,
        )


class PointUpdate(_Body):
    """A change of a point: the fields given replace the old ones (``name`` renames it)."""

    name: Name | None = None
    x: Finite | None = None
    y: Finite | None = None
    theta: Finite | None = None
    kind: KindName | None = None
    number: int | None = None

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

    map: Name
    point: Name | None = None
    x: Finite | None = None
    y: Finite | None = None
    theta: Finite | None = None

    @model_validator(mode="after")
    def _one_origin(self) -> NavigationStartIn:
        pose = _pose_or_none(self.x, self.y, self.theta)
        if pose is not None and self.point is not None:
            raise ValueError("give a point or a pose, not both")
        return self

    def pose(self) -> Pose2D | None:
        return _pose_or_none(self.x, self.y, self.theta)


class GoalIn(_Body):
    """A navigation goal: a named point, or a pose (on the current map unless ``map`` is set)."""

    point: Name | None = None
    x: Finite | None = None
    y: Finite | None = None
    theta: Finite | None = None
    map: Name | None = None

    @model_validator(mode="after")
    def _point_or_pose(self) -> GoalIn:
        pose = _pose_or_none(self.x, self.y, self.theta)
        if (pose is None) == (self.point is None):
            raise ValueError("give either a point or x and y")
        return self

    def pose(self) -> Pose2D | None:
        return _pose_or_none(self.x, self.y, self.theta)


class GoalAccepted(BaseModel):
    """A goal was accepted; ``id`` names its navigation attempt in events."""

    id: int


# --- control ----------------------------------------------------------------------------------


class TeleopIn(_Body):
    """A velocity command [m/s, rad/s], clamped to the settings; repeat it within the dead-man
    timeout or the base stops."""

    linear: Finite
    angular: Finite = 0.0


class EStopIn(_Body):
    """The software emergency stop (the hardware button is separate)."""

    on: bool


class LocalMoveIn(_Body):
    """Rotate by an angle [rad] or drive straight a distance [m] (negative: backwards)."""

    rotate: Finite | None = None
    distance: Finite | None = None

    @model_validator(mode="after")
    def _exactly_one(self) -> LocalMoveIn:
        if (self.rotate is None) == (self.distance is None):
            raise ValueError("give exactly one of rotate or distance")
        return self
