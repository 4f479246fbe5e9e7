"""Recovery behaviours tried before a navigation attempt gives up (Nav2's behaviour server).

Each behaviour is a small state machine advanced once per control period: ``start`` arms it,
``tick`` returns the velocity to command or ``None`` once it is done. They run on ``now`` and the
pose estimate only, so they work the same in simulation and on hardware.

After a block the navigator climbs a *ladder* (:class:`Ladder`, :func:`ladder_rung`): each new
failure at the same place runs one more rung before the re-plan. Clear the lidar's marks around
the robot (stale marks and noise are the commonest false block), back up (out of a wedge, so the
body has room to turn), rotate (the lidar sweeps what the body hid, and a polygon turns toward
the way on), wait (a person or a door moves on). Motions check the real footprint
(:mod:`polynav.footprint`) against LETHAL cells before each step, so a recovery never drives the
robot into what it is recovering from.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

import numpy as np
import numpy.typing as npt

from polynav import footprint as body
from polynav.footprint import Footprint
from polynav.geometry import Pose2D, Twist, angle_diff
from polynav.maps import costs
from polynav.maps.map import MapInfo


class ObstacleClearing(Protocol):
    def clear_obstacles(self) -> None: ...

    def cost_at(self, x: float, y: float) -> int: ...


class LocalClearing(ObstacleClearing, Protocol):
    """What the ladder needs of a costmap: local clearing and the grid to check the body on."""

    def clear_obstacles_around(self, x: float, y: float, radius: float) -> None: ...

    @property
    def info(self) -> MapInfo: ...

    @property
    def costs(self) -> npt.NDArray[np.uint8]: ...


class Recovery(Protocol):
    name: str

    def start(self, pose: Pose2D, now: float) -> None: ...

    def tick(self, pose: Pose2D, now: float) -> Twist | None: ...


class ClearCostmap:
    """Forget every obstacle the lidar has marked: stale marks are the commonest false block."""

    name = "clear costmap"

    def __init__(self, costmap: ObstacleClearing) -> None:
        self._costmap = costmap

    def start(self, pose: Pose2D, now: float) -> None:
        self._costmap.clear_obstacles()

    def tick(self, pose: Pose2D, now: float) -> Twist | None:
        return None


@dataclass
class Spin:
    """Turn in place by ``angle`` [rad] so the lidar sweeps the surroundings into the costmap."""

    angle: float = math.pi / 2
    angular_speed: float = 1.0
    timeout: float = 6.0
    name: str = "spin"

    def __post_init__(self) -> None:
        self._turned = 0.0
        self._last_theta = 0.0
        self._started = 0.0

    def start(self, pose: Pose2D, now: float) -> None:
        self._turned = 0.0
        self._last_theta = pose.theta
        self._started = now

    def tick(self, pose: Pose2D, now: float) -> Twist | None:
        self._turned += abs(angle_diff(pose.theta, self._last_theta))
        self._last_theta = pose.theta
        if self._turned >= abs(self.angle) or now - self._started >= self.timeout:
            return None
        return Twist(0.0, math.copysign(self.angular_speed, self.angle))


class BackUp:
    """Reverse a short distance [m], stopping early if the way behind is blocked.

    With a ``footprint`` (and a costmap that is a cost grid) the body itself is placed along the
    next stretch behind and checked against LETHAL cells, and UNKNOWN ones: the robot backs only
    onto floor it has seen free. The ladder clears the marks around the robot just before this
    rung; a robot whose lidar sees behind marks them again with the next scan (so the ladder's
    back-up first stands ``settle`` [s] for one), but one blind behind (a 270° lidar) does not, and
    without a map the cleared posts behind it were only unknown floor to the check: the
    delivery robot backed into one (lattice course 61 without a map). Without a footprint, the
    cell one radius plus a margin behind the centre is looked up.
    """

    name = "back up"

    def __init__(
        self,
        costmap: ObstacleClearing,
        *,
        distance: float = 0.25,
        speed: float = 0.1,
        robot_radius: float = 0.25,
        timeout: float = 5.0,
        footprint: Footprint | None = None,
        settle: float = 0.0,
    ) -> None:
        self._costmap = costmap
        self.settle = settle
        self.distance = distance
        self.speed = speed
        self.robot_radius = robot_radius
        self.timeout = timeout
        self.footprint = footprint
        self._origin = Pose2D()
        self._started = 0.0

    def start(self, pose: Pose2D, now: float) -> None:
        self._origin = pose
        self._started = now

    def tick(self, pose: Pose2D, now: float) -> Twist | None:
        if pose.distance_to(self._origin) >= self.distance or now - self._started >= self.timeout:
            return None
        if self.footprint is not None:
            if now - self._started < self.settle:
                return Twist()  # the next scan marks again what the clearing forgot
            return None if self._body_blocked(pose) else Twist(-self.speed, 0.0)
        # Look one radius plus a margin behind the footprint's edge before each step back.
        probe = self.robot_radius + 0.1
        bx = pose.x - probe * math.cos(pose.theta)
        by = pose.y - probe * math.sin(pose.theta)
        if self._costmap.cost_at(bx, by) >= costs.LETHAL:
            return None
        return Twist(-self.speed, 0.0)

    def _body_blocked(self, pose: Pose2D) -> bool:
        """Would the body, backing on by a few centimetres, overlap a LETHAL cell?"""
        assert self.footprint is not None
        grid: LocalClearing = self._costmap  # type: ignore[assignment]
        step = 0.5 * grid.info.resolution
        back = np.arange(step, 0.1 + step, step)
        c, s = math.cos(pose.theta), math.sin(pose.theta)
        poses = np.column_stack(
            (pose.x - c * back, pose.y - s * back, np.full(back.shape, pose.theta))
        )
        # Already touching a mark (wedged): back up unless something new is behind.
        poses = np.vstack(([pose.x, pose.y, pose.theta], poses))
        return body.first_collision(self.footprint, grid, poses, unknown_is_lethal=True,
                                    ignore_start=True) is not None


class ClearAround:
    """Forget the lidar's marks within ``radius`` [m] of the robot; the rest of the map keeps."""

    name = "clear around"

    def __init__(self, costmap: LocalClearing, *, radius: float = 1.5) -> None:
        self._costmap = costmap
        self.radius = radius

    def start(self, pose: Pose2D, now: float) -> None:
        self._costmap.clear_obstacles_around(pose.x, pose.y, self.radius)

    def tick(self, pose: Pose2D, now: float) -> Twist | None:
        return None


class Rotate:
    """Turn in place by up to ``angle`` [rad], the way that faces ``toward`` if that is clear.

    The direction is chosen at start: the one that brings the heading toward the point
    ``toward`` (the goal), unless sweeping the footprint that way hits a LETHAL cell and the
    other way does not. The turn stops early where the sweep would next hit something.
    """

    name = "rotate"

    def __init__(
        self,
        costmap: LocalClearing,
        *,
        footprint: Footprint,
        angle: float = math.pi / 2,
        angular_speed: float = 0.8,
        timeout: float = 6.0,
    ) -> None:
        self._costmap = costmap
        self.footprint = footprint
        self.angle = angle
        self.angular_speed = angular_speed
        self.timeout = timeout
        self.toward: tuple[float, float] | None = None
        self._turn = 0.0
        self._turned = 0.0
        self._last_theta = 0.0
        self._started = 0.0

    def start(self, pose: Pose2D, now: float) -> None:
        self._started = now
        self._turned = 0.0
        self._last_theta = pose.theta
        preferred = self.angle
        if self.toward is not None:
            bearing = angle_diff(
                math.atan2(self.toward[1] - pose.y, self.toward[0] - pose.x), pose.theta
            )
            preferred = math.copysign(min(abs(bearing), self.angle), bearing)
            if abs(preferred) < 0.1:
                preferred = math.copysign(self.angle, bearing or 1.0)
        self._turn = 0.0
        for turn in (preferred, -math.copysign(self.angle, preferred)):
            if not self._sweep_hits(pose, turn):
                self._turn = turn
                break

    def tick(self, pose: Pose2D, now: float) -> Twist | None:
        self._turned += abs(angle_diff(pose.theta, self._last_theta))
        self._last_theta = pose.theta
        left = abs(self._turn) - self._turned
        if left <= 0.02 or now - self._started >= self.timeout:
            return None
        # Re-check the next stretch of the sweep against what the lidar shows now.
        if self._sweep_hits(pose, math.copysign(min(left, 0.3), self._turn)):
            return None
        return Twist(0.0, math.copysign(min(self.angular_speed, 2.0 * left + 0.1), self._turn))

    def _sweep_hits(self, pose: Pose2D, turn: float) -> bool:
        if self.footprint.is_circle or turn == 0.0:
            return turn == 0.0
        poses = body.rotation_poses(self.footprint, pose, turn, self._costmap.info.resolution)
        # Touching already: turning is allowed as long as it touches nothing new.
        hit = body.first_collision(self.footprint, self._costmap, poses, ignore_start=True)
        return hit is not None


@dataclass
class Wait:
    """Stand still for ``duration`` [s]: a person or a door may move on."""

    duration: float = 2.0
    name: str = "wait"

    def __post_init__(self) -> None:
        self._until = 0.0

    def start(self, pose: Pose2D, now: float) -> None:
        self._until = now + self.duration

    def tick(self, pose: Pose2D, now: float) -> Twist | None:
        return None if now >= self._until else Twist()


class Ladder:
    """Run ``steps`` one after the other; done when the last is done."""

    def __init__(self, steps: Sequence[Recovery]) -> None:
        self.steps = tuple(steps)
        self.name = ", ".join(step.name for step in self.steps)
        self._index = 0

    def start(self, pose: Pose2D, now: float) -> None:
        self._index = 0
        if self.steps:
            self.steps[0].start(pose, now)

    def tick(self, pose: Pose2D, now: float) -> Twist | None:
        while self._index < len(self.steps):
            twist = self.steps[self._index].tick(pose, now)
            if twist is not None:
                return twist
            self._index += 1
            if self._index < len(self.steps):
                self.steps[self._index].start(pose, now)
        return None


def ladder_rung(steps: Sequence[Recovery], rung: int) -> Ladder:
    """The recovery for the ``rung``-th failure at one place (1 = the first): its first
    ``rung`` steps, all of them from then on."""
    return Ladder(steps[: max(1, min(rung, len(steps)))])
