"""Planar geometry: poses, rigid transforms, angle wrapping and yaw/quaternion conversion.

Every angle inside polynav is in radians and wrapped into (-pi, pi] by :func:`wrap_angle`; every
length is in metres. A :class:`Pose2D` is also the rigid transform that maps points from its own
frame into the parent frame, so composition and inversion are the usual SE(2) operations.
"""

from __future__ import annotations

import math
from dataclasses import dataclass


def wrap_angle(angle: float) -> float:
    """Wrap an angle [rad] into (-pi, pi]."""
    wrapped = math.fmod(angle + math.pi, 2.0 * math.pi)
    if wrapped <= 0.0:
        wrapped += 2.0 * math.pi
    return wrapped - math.pi


def angle_diff(a: float, b: float) -> float:
    """Signed smallest rotation [rad] that takes heading ``b`` to heading ``a``."""
    return wrap_angle(a - b)


def yaw_to_quaternion(yaw: float) -> tuple[float, float, float, float]:
    """Quaternion (x, y, z, w) of a rotation by ``yaw`` [rad] about +z."""
    half = 0.5 * yaw
    return (0.0, 0.0, math.sin(half), math.cos(half))


def quaternion_to_yaw(x: float, y: float, z: float, w: float) -> float:
    """Yaw [rad] of a quaternion (x, y, z, w); roll and pitch are ignored.

    The quaternion need not be normalised: atan2 takes the ratio.
    """
    siny_cosp = 2.0 * (w * z + x * y)
    cosy_cosp = w * w + x * x - y * y - z * z
    return wrap_angle(math.atan2(siny_cosp, cosy_cosp))


@dataclass(frozen=True, slots=True)
class Pose2D:
    """A planar pose: position [m] and heading [rad] in a parent frame (usually the map)."""

    x: float = 0.0
    y: float = 0.0
    theta: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "theta", wrap_angle(self.theta))

    def compose(self, other: Pose2D) -> Pose2D:
        """``self ∘ other``: ``other`` is expressed in this pose's frame; result in the parent."""
        c, s = math.cos(self.theta), math.sin(self.theta)
        return Pose2D(
            self.x + c * other.x - s * other.y,
            self.y + s * other.x + c * other.y,
            self.theta + other.theta,
        )

    def inverse(self) -> Pose2D:
        """The transform that undoes this one."""
        c, s = math.cos(self.theta), math.sin(self.theta)
        return Pose2D(-c * self.x - s * self.y, s * self.x - c * self.y, -self.theta)

    def relative_to(self, base: Pose2D) -> Pose2D:
        """This pose expressed in ``base``'s frame (``base⁻¹ ∘ self``)."""
        return base.inverse().compose(self)

    def transform_point(self, px: float, py: float) -> tuple[float, float]:
        """A point given in this pose's frame, expressed in the parent frame."""
        c, s = math.cos(self.theta), math.sin(self.theta)
        return (self.x + c * px - s * py, self.y + s * px + c * py)

    def distance_to(self, other: Pose2D) -> float:
        """Euclidean distance [m] between the two positions."""
        return math.hypot(other.x - self.x, other.y - self.y)

    def heading_error_to(self, other: Pose2D) -> float:
        """Signed rotation [rad] from this heading to ``other``'s heading."""
        return angle_diff(other.theta, self.theta)


@dataclass(frozen=True, slots=True)
class Twist:
    """A planar velocity: forward speed [m/s] and turn rate [rad/s] in the robot frame."""

    linear: float = 0.0
    angular: float = 0.0
