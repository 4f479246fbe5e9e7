"""GET /api/robot: the robot's profile; POST /api/robot/check: check a profile without using it.

The profile (:mod:`polynav.robot.profile`) is what the simulator and the navigation stack were
built from: body, limits, cruise speeds, lidar, odometry and IMU noise, charger contact. It is
fixed for the runtime's life (a body does not change while it drives), so there is no PUT; a
client editing a ``robot.yaml`` can have it checked here with the same rules as ``polynav run
--robot``: a body the document refuses is a 422, a profile that contradicts itself (a crossing
polygon, a lidar off the body, a cruise above the limits) a 409 naming the field.
"""

from __future__ import annotations

import logging
from typing import Annotated, Any

from fastapi import APIRouter, Body
from pydantic import BaseModel, BeforeValidator, ConfigDict, Field

from polynav.api.deps import RuntimeDep
from polynav.api.errors import BODY, STATE, responses
from polynav.robot.profile import parse_profile

log = logging.getLogger(__name__)

router = APIRouter(prefix="/api/robot", tags=["robot"])

# Bounds keep every number a profile can hold far from overflow; the profile's own rules are
# narrower (positive speeds, a lidar on the body ...) and name the field when broken.
_BIG = 1.0e6
Number = Annotated[float, Field(strict=True, allow_inf_nan=False, ge=-_BIG, le=_BIG)]
def _integral(value: object) -> object:
    """JSON Schema's ``integer`` takes 360.0 too: a float with no fraction is that integer."""
    if isinstance(value, float) and value.is_integer():
        return int(value)
    return value


Beams = Annotated[int, Field(strict=True, ge=1, le=100_000), BeforeValidator(_integral)]
Vertex = Annotated[list[Number], Field(min_length=2, max_length=2)]


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid")


class FootprintIO(_Strict):
    """A circle (``radius``) or a polygon (``polygon``, base frame: x forward, y left) [m]."""

    radius: Number | None = None
    polygon: Annotated[list[Vertex], Field(max_length=64)] | None = None


class LimitsIO(_Strict):
    """Speed [m/s, rad/s] and acceleration [m/s², rad/s²] limits of the base."""

    max_linear_velocity: Number | None = None
    max_angular_velocity: Number | None = None
    linear_acceleration: Number | None = None
    linear_deceleration: Number | None = None
    angular_acceleration: Number | None = None
    angular_deceleration: Number | None = None


class CruiseIO(_Strict):
    """How navigation drives by default, within the limits."""

    linear_velocity: Number | None = None
    angular_velocity: Number | None = None
    linear_acceleration: Number | None = None
    linear_deceleration: Number | None = None
    angular_acceleration: Number | None = None


class MountIO(_Strict):
    """A pose on the base [m, rad]."""

    x: Number | None = None
    y: Number | None = None
    theta: Number | None = None


class LidarIO(_Strict):
    """The lidar: its mount and how it measures [m, rad, Hz]."""

    pose: MountIO | None = None
    range_min: Number | None = None
    range_max: Number | None = None
    fov: Number | None = None
    beams: Beams | None = None
    rate: Number | None = None
    noise: Number | None = None


class OdometryIO(_Strict):
    """Wheel odometry noise."""

    translation_noise: Number | None = None
    rotation_noise: Number | None = None
    translation_additive: Number | None = None
    rotation_additive: Number | None = None


class ImuIO(_Strict):
    """IMU rate [Hz] and noise."""

    rate: Number | None = None
    yaw_rate_noise: Number | None = None
    yaw_rate_bias: Number | None = None
    acceleration_noise: Number | None = None


class ChargerIO(_Strict):
    """How precisely the base must stand on a charger point [m, rad], and the shape of the
    charger's front plate docking finds in the scan (its width, its notch's width and depth) [m]."""

    distance_tolerance: Number | None = None
    heading_tolerance: Number | None = None
    plate_width: Number | None = None
    notch_width: Number | None = None
    notch_depth: Number | None = None


class SignCameraIO(_Strict):
    """A forward camera that spots "no entry" signs: how far [m] and how wide [rad] it sees."""

    range: Number | None = None
    fov: Number | None = None


class PayloadIO(_Strict):
    """What the robot can carry on its jack or latch [kg], and how it drives loaded: cruise
    speeds [m/s, rad/s] and acceleration [m/s²], none above the unloaded cruise."""

    max_mass: Number | None = None
    linear_velocity: Number | None = None
    angular_velocity: Number | None = None
    linear_acceleration: Number | None = None


class ReverseIO(_Strict):
    """May the base back up in a recovery, and how far [m] behind it its sensors see (left out:
    the lidar's range if it sees behind, else 0)."""

    allowed: Annotated[bool, Field(strict=True)] | None = None
    rear_view: Number | None = None


class ProfileIn(_Strict):
    """A robot profile, as in ``robot.yaml``; left-out sections take the defaults."""

    name: Annotated[str, Field(min_length=1, max_length=200)]
    description: Annotated[str, Field(max_length=2000)] = ""
    footprint: FootprintIO
    limits: LimitsIO | None = None
    cruise: CruiseIO | None = None
    lidar: LidarIO | None = None
    odometry: OdometryIO | None = None
    imu: ImuIO | None = None
    charger: ChargerIO | None = None
    reverse: ReverseIO | None = None
    sign_camera: SignCameraIO | None = None
    payload: PayloadIO | None = None


class ProfileOut(BaseModel):
    """A robot profile with every value filled in, and its body's radii [m]."""

    name: str
    description: str
    footprint: FootprintIO
    inscribed_radius: float = Field(description="largest disk about the centre inside the body")
    circumscribed_radius: float = Field(description="smallest disk about the centre holding it")
    limits: LimitsIO
    cruise: CruiseIO
    lidar: LidarIO
    odometry: OdometryIO
    imu: ImuIO
    charger: ChargerIO
    reverse: ReverseIO
    sign_camera: SignCameraIO | None = Field(
        default=None, description="only for robots with one")
    payload: PayloadIO | None = Field(
        default=None, description="only for robots that carry carts or cabins")


ProfileBody = Body(
    description="a robot profile, as in robot.yaml",
    examples=[{"name": "round", "footprint": {"radius": 0.2},
               "limits": {"max_linear_velocity": 1.5}}],
)


@router.get("", operation_id="get_robot", response_model=ProfileOut)
def get_robot(runtime: RuntimeDep) -> dict[str, Any]:
    """The profile the robot runs with: the simulator and the navigation stack were built from
    it, and speed settings may not exceed its limits nor the planning footprint its body."""
    return dict(runtime.profile.to_dict())


@router.post(
    "/check",
    operation_id="check_robot_profile",
    response_model=ProfileOut,
    responses=responses(BODY, STATE),
)
def check_robot_profile(profile: ProfileIn = ProfileBody) -> dict[str, Any]:
    """Check a profile by the rules of ``polynav run --robot`` without using it: answers the
    profile with every default filled in, or 409 naming the field that is inconsistent (a
    negative speed, a self-intersecting polygon, a lidar off the body, an unknown key)."""
    doc = profile.model_dump(exclude_none=True)
    return dict(parse_profile(doc).to_dict())
