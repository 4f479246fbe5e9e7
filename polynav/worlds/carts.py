"""Carts and cabins: the loads of a building a robot docks to, carries and leaves.

A **cart** (Yunji's *container*) is a frame on four legs, tall enough for the robot to drive
under between its legs; the robot raises its jacking axis under the frame and the cart rides on
it. A **cabin** (a *mobile cabin*) is a closed box on four corner posts that the robot drives
into and latches to; a tag reader in the latch reads the cabin's id, so a robot sent to the
wrong cabin finds out before it carries it away. The robot's lidar is mounted low: it sees a
cart's legs and a cabin's corner posts, never the frame or the walls above them, so both look
alike in a scan (four posts in a rectangle) and are told apart by the world, not the scan.

A :class:`WorldCart` is where one stands at the start: its centre, its heading (the way a
docked robot faces: it drives in along it) and its legs' rectangle (``length`` along the
heading, ``width`` across). :func:`leg_positions` places the legs at any pose, which is what
the simulator does as the cart is carried.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

from polynav.errors import InvalidRequest
from polynav.footprint import Footprint
from polynav.geometry import Pose2D

LEG_RADIUS = 0.03
"""[m] a leg's (or a corner post's) radius, as the lidar sees it."""


class CartKind(enum.Enum):
    """A ``cart`` is lifted by the jacking axis; a ``cabin`` is latched (and has an id)."""

    CART = "cart"
    CABIN = "cabin"


@dataclass(frozen=True, slots=True)
class WorldCart:
    """One cart or cabin of the building, where it stands when the world starts.

    Attributes:
        name: the object's id (``cart_1``).
        kind: cart or cabin.
        floor: the floor it stands on.
        pose: its centre and heading (a docked robot stands at its centre facing this way).
        length: distance [m] between the front and back legs' centres (along the heading).
        width: distance [m] between the left and right legs' centres (across it).
        mass: loaded mass [kg]; a robot carries only what its profile allows.
        cabin_id: what the latch's tag reader reads (cabins only).
        leg_radius: radius [m] of each leg or post.
    """

    name: str
    kind: CartKind
    floor: str
    pose: Pose2D
    length: float = 0.9
    width: float = 0.7
    mass: float = 40.0
    cabin_id: str | None = None
    leg_radius: float = LEG_RADIUS

    def __post_init__(self) -> None:
        if not self.name:
            raise InvalidRequest("name", f"a {self.kind.value} needs a name")
        if not self.floor:
            raise InvalidRequest("floor", f"{self.kind.value} {self.name!r} is on no floor")
        for key in ("length", "width", "leg_radius"):
            value = getattr(self, key)
            if not (math.isfinite(value) and value > 0.0):
                raise InvalidRequest(key, f"{self.name!r}: must be > 0, got {value}")
        if not (math.isfinite(self.mass) and self.mass >= 0.0):
            raise InvalidRequest("mass", f"{self.name!r}: must be >= 0 [kg], got {self.mass}")
        if self.kind is CartKind.CABIN and not self.cabin_id:
            raise InvalidRequest("cabin_id", f"cabin {self.name!r} needs the id its tag carries")
        if self.kind is CartKind.CART and self.cabin_id is not None:
            raise InvalidRequest("cabin_id", f"cart {self.name!r}: only a cabin has a cabin id")
        if 2.0 * self.leg_radius >= min(self.length, self.width):
            raise InvalidRequest("leg_radius", f"{self.name!r}: legs wider than the frame")

    @property
    def clear_width(self) -> float:
        """The free width [m] between the left and right legs: what a robot drives in through."""
        return self.width - 2.0 * self.leg_radius

    def legs(self, pose: Pose2D | None = None) -> tuple[tuple[float, float], ...]:
        """The legs' centres [m] with the object at ``pose`` (default: where it starts)."""
        return leg_positions(pose or self.pose, self.length, self.width)


def leg_positions(pose: Pose2D, length: float, width: float) -> tuple[tuple[float, float], ...]:
    """The four legs' centres of a frame ``length`` × ``width`` centred at ``pose``: front
    left, front right, back right, back left."""
    c, s = math.cos(pose.theta), math.sin(pose.theta)
    out = []
    for lx, ly in ((0.5 * length, 0.5 * width), (0.5 * length, -0.5 * width),
                   (-0.5 * length, -0.5 * width), (-0.5 * length, 0.5 * width)):
        out.append((pose.x + c * lx - s * ly, pose.y + s * lx + c * ly))
    return tuple(out)


def entry_pose(pose: Pose2D, length: float, clearance: float) -> Pose2D:
    """Where a robot waits before driving in: on the object's axis, behind its back legs by
    ``clearance`` [m] (the robot's reach plus a margin), facing in."""
    return pose.compose(Pose2D(-(0.5 * length + clearance), 0.0, 0.0))


def carried_footprint(body: Footprint, load: Pose2D, length: float, width: float,
                      leg_radius: float = LEG_RADIUS) -> Footprint:
    """The outline the robot plans and drives with while it carries a load: the convex hull
    of its body and of the load's frame (its legs' rectangle grown by a leg's radius) standing
    at ``load`` in the base frame. A hull, not the union: the planner's checks take one
    polygon, and what lies between body and load is not worth squeezing through."""
    hx, hy = 0.5 * length + leg_radius, 0.5 * width + leg_radius
    c, s = math.cos(load.theta), math.sin(load.theta)
    corners = [(load.x + c * x - s * y, load.y + s * x + c * y)
               for x, y in ((hx, hy), (-hx, hy), (-hx, -hy), (hx, -hy))]
    pts = [(float(x), float(y)) for x, y in body.outline(Pose2D(), segments=16)] + corners
    return Footprint.polygon(_hull(pts), key="carried")


def _hull(points: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """The convex hull, counter-clockwise (Andrew's monotone chain)."""
    pts = sorted(set(points))

    def cross(o: tuple[float, float], a: tuple[float, float], b: tuple[float, float]) -> float:
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower: list[tuple[float, float]] = []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 1e-12:
            lower.pop()
        lower.append(p)
    upper: list[tuple[float, float]] = []
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 1e-12:
            upper.pop()
        upper.append(p)
    return lower[:-1] + upper[:-1]
