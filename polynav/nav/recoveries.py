"""Recovery behaviours tried before a navigation attempt gives up (Nav2's behaviour server).

Each behaviour is a small state machine advanced once per control period: ``start`` arms it,
``tick`` returns the velocity to command or ``None`` once it is done. They run on ``now`` and the
pose estimate only, so they work the same in simulation and on hardware.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

from polynav.geometry import Pose2D, Twist, angle_diff
from polynav.maps import costs


class ObstacleClearing(Protocol):
    def clear_obstacles(self) -> None: ...

    def cost_at(self, x: float, y: float) -> int: ...


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
    """Reverse a short distance [m], stopping early if the cell behind the robot is an obstacle."""

    name = "back up"

    def __init__(
        self,
        costmap: ObstacleClearing,
        *,
        distance: float = 0.25,
        speed: float = 0.1,
        robot_radius: float = 0.25,
        timeout: float = 5.0,
    ) -> None:
        self._costmap = costmap
        self.distance = distance
        self.speed = speed
        self.robot_radius = robot_radius
        self.timeout = timeout
        self._origin = Pose2D()
        self._started = 0.0

    def start(self, pose: Pose2D, now: float) -> None:
        self._origin = pose
        self._started = now

    def tick(self, pose: Pose2D, now: float) -> Twist | None:
        if pose.distance_to(self._origin) >= self.distance or now - self._started >= self.timeout:
            return None
        # Look one radius plus a margin behind the footprint's edge before each step back.
        probe = self.robot_radius + 0.1
        bx = pose.x - probe * math.cos(pose.theta)
        by = pose.y - probe * math.sin(pose.theta)
        if self._costmap.cost_at(bx, by) >= costs.LETHAL:
            return None
        return Twist(-self.speed, 0.0)
