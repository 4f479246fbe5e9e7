"""The simulator's carts and cabins: legs the lidar sees and bodies bump into, carried rigidly.

Each ``carts:`` entry of the world is a :class:`SimCart` of the scene's :class:`CartYard`. Its
four legs (a cabin's corner posts) are discs of ``leg_radius`` on its floor: the lidar sees them
as it sees people (circles), and a body that would newly overlap one is stopped (a collision
with a ``"wall"``). Between the legs the robot passes freely: the frame and a cabin's walls are
above the lidar and the base, which is what lets the robot drive under a cart or into a cabin.

A robot takes a load by standing under it within :data:`ALIGN_DISTANCE` and
:data:`ALIGN_HEADING` of its centre and heading, then raising its jacking axis above
:data:`LIFT_HEIGHT` (a cart) or closing its latch (a cabin, :meth:`CartYard.latch`). From then
on the load keeps its pose in the robot's frame: it moves, turns and rides lifts with the
robot, and its legs go where it goes. The carrier's own lidar does not see its load's legs (a
real robot masks them out of its scan, as a ROS box filter does), and its collision check takes
the legs along: a carried leg that would newly overlap a wall stops the robot. Lowering the
jack (or opening the latch) leaves the load where it stands.

What the robot can carry (the profile's ``payload``) is the runtime's check, before it lifts:
the simulator only moves what is lifted.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from polynav.errors import Conflict
from polynav.geometry import Pose2D, angle_diff
from polynav.robot.sim.charger import points_clearance
from polynav.worlds.carts import CartKind, WorldCart, leg_positions

log = logging.getLogger(__name__)

ALIGN_DISTANCE = 0.1
"""[m] how far from a load's centre a robot may stand and still lift or latch it."""

ALIGN_HEADING = 0.2
"""[rad] how far from a load's heading a robot may face and still lift or latch it."""

LIFT_HEIGHT = 0.03
"""[m] the jacking axis above this height holds a cart it is under off the floor."""

NO_LEGS = np.empty((0, 3), dtype=np.float64)


@dataclass(slots=True)
class SimCart:
    """One cart or cabin: where it stands, or who carries it (and where on the carrier)."""

    spec: WorldCart
    floor: str
    pose: Pose2D
    carrier: str | None = None
    offset: Pose2D = field(default_factory=Pose2D)
    """The load's pose in its carrier's frame while carried."""
    _legs_at: Pose2D | None = field(default=None, init=False, repr=False, compare=False)
    _legs: npt.NDArray[np.float64] = field(default_factory=lambda: NO_LEGS, init=False,
                                           repr=False, compare=False)

    @property
    def name(self) -> str:
        return self.spec.name

    @property
    def reach(self) -> float:
        """[m] from its centre to its legs' centres: a leg is no nearer to a point than the
        centre's distance less this."""
        return math.hypot(0.5 * self.spec.length, 0.5 * self.spec.width)

    def legs(self) -> npt.NDArray[np.float64]:
        """(4, 3) rows x, y, radius [m] of its legs, world frame (read-only).

        Cached for the pose they were computed at: a :class:`Pose2D` is frozen and the spec
        too, so the legs change only when ``pose`` is given a new object (every move does),
        which the identity check catches.
        """
        if self._legs_at is not self.pose:
            r = self.spec.leg_radius
            legs = np.array([(x, y, r) for x, y in
                             leg_positions(self.pose, self.spec.length, self.spec.width)],
                            dtype=np.float64)
            legs.flags.writeable = False
            self._legs, self._legs_at = legs, self.pose
        return self._legs

    def aligned(self, pose: Pose2D) -> bool:
        """Whether a base at ``pose`` stands under (in) it, close enough to take it."""
        return (pose.distance_to(self.pose) <= ALIGN_DISTANCE
                and abs(angle_diff(pose.theta, self.pose.theta)) <= ALIGN_HEADING)


class CartYard:
    """Every cart and cabin of a scene (see the module docstring)."""

    def __init__(self, carts: tuple[WorldCart, ...]) -> None:
        self.carts: dict[str, SimCart] = {c.name: SimCart(c, c.floor, c.pose) for c in carts}

    def carried_by(self, body: str) -> SimCart | None:
        """The load ``body`` carries, if any."""
        for cart in self.carts.values():
            if cart.carrier == body:
                return cart
        return None

    def under(self, body: str, floor: str, pose: Pose2D,
              kind: CartKind | None = None) -> SimCart | None:
        """The load standing free on ``floor`` that a base at ``pose`` is aligned under."""
        for cart in self.carts.values():
            if (cart.carrier is None and cart.floor == floor and cart.aligned(pose)
                    and (kind is None or cart.spec.kind is kind)):
                return cart
        return None

    def legs(self, floor: str, *, mask: str | None = None) -> npt.NDArray[np.float64]:
        """(K, 3) rows x, y, radius of every leg on ``floor``, but those of the load ``mask``
        carries (its own lidar and collision check leave them out)."""
        rows = [c.legs() for c in self.carts.values()
                if c.floor == floor and (mask is None or c.carrier != mask)]
        return np.concatenate(rows) if rows else NO_LEGS

    def take(self, cart: SimCart, body: str, pose: Pose2D) -> None:
        """``body``, at ``pose``, now carries ``cart``.

        Raises:
            Conflict: it carries another load, or someone else carries this one.
        """
        held = self.carried_by(body)
        if held is not None and held is not cart:
            raise Conflict(f"{body} already carries {held.name}")
        if cart.carrier not in (None, body):
            raise Conflict(f"{cart.name} is carried by {cart.carrier}")
        cart.carrier = body
        cart.offset = cart.pose.relative_to(pose)
        log.info("%s takes %s %s on %s", body, cart.spec.kind.value, cart.name, cart.floor)

    def release(self, body: str) -> SimCart | None:
        """``body`` sets its load down where it stands; the load, or None if it had none."""
        cart = self.carried_by(body)
        if cart is not None:
            cart.carrier = None
            log.info("%s leaves %s on %s at (%.3f, %.3f, %.3f)", body, cart.name, cart.floor,
                     cart.pose.x, cart.pose.y, cart.pose.theta)
        return cart

    def follow(self, body: str, floor: str, pose: Pose2D) -> None:
        """Move ``body``'s load with it (after every step and teleport)."""
        cart = self.carried_by(body)
        if cart is not None:
            cart.floor = floor
            cart.pose = _normalized(pose.compose(cart.offset))

    def jack(self, body: str, floor: str, pose: Pose2D, height: float) -> SimCart | None:
        """The jacking axis of ``body`` stands at ``height`` [m]: above :data:`LIFT_HEIGHT` it
        holds the cart it is aligned under; below, it sets its cart down. The cart now held."""
        held = self.carried_by(body)
        if height >= LIFT_HEIGHT:
            if held is None:
                cart = self.under(body, floor, pose, CartKind.CART)
                if cart is not None:
                    self.take(cart, body, pose)
                    return cart
            return held
        if held is not None and held.spec.kind is CartKind.CART:
            self.release(body)
        return None

    def clearance(self, body: str, floor: str, pose: Pose2D, radius: float,
                  polygon: tuple[tuple[float, float], ...],
                  wall_gap: Callable[[float, float, float], float]) -> float:
        """Signed gap [m] between ``body`` at ``pose`` (a disk of ``radius`` or ``polygon``)
        and the legs on ``floor`` (its own load's aside), and between its load's legs there
        and the walls (``wall_gap(x, y, r)``: a disc's gap to the walls)."""
        # Only carts whose centre is within reach of the near band can have a leg in it (the
        # margin covers rounding); the others' legs would all fail the ``near`` test below.
        band = radius + 0.5
        rows = [c.legs() for c in self.carts.values()
                if c.floor == floor and c.carrier != body
                and math.hypot(c.pose.x - pose.x, c.pose.y - pose.y) <= band + c.reach + 1e-6]
        gap = math.inf
        if rows:
            legs = np.concatenate(rows)
            near = legs[np.hypot(legs[:, 0] - pose.x, legs[:, 1] - pose.y) <= band]
            if near.shape[0]:
                gap = points_clearance(pose, radius, polygon, near[:, :2]) - float(
                    near[:, 2].max())
        load = self.carried_by(body)
        if load is not None:
            for x, y in self.carried_legs(body, pose):
                gap = min(gap, wall_gap(float(x), float(y), load.spec.leg_radius))
        return gap

    def carried_legs(self, body: str, pose: Pose2D) -> npt.NDArray[np.float64]:
        """(4, 2) world x, y of ``body``'s load's legs were the body at ``pose`` (none if it
        carries nothing)."""
        cart = self.carried_by(body)
        if cart is None:
            return np.empty((0, 2), dtype=np.float64)
        at = pose.compose(cart.offset)
        return np.array(leg_positions(at, cart.spec.length, cart.spec.width),
                        dtype=np.float64)


def _normalized(pose: Pose2D) -> Pose2D:
    return Pose2D(pose.x, pose.y, math.remainder(pose.theta, 2.0 * math.pi))
