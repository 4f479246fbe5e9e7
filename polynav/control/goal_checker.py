"""Has the robot reached its goal? Position first, then heading, with a latch.

Like Nav2's stateful ``SimpleGoalChecker``: once the position is within tolerance the checker
remembers it, so the centimetre of jitter a localization estimate shows while the robot turns to the
goal heading cannot send it back to driving (which would make it dance around the goal).
"""

from __future__ import annotations

from dataclasses import dataclass

from polynav.errors import ConfigError
from polynav.geometry import Pose2D


@dataclass(frozen=True, slots=True)
class GoalCheckerConfig:
    xy_tolerance: float = 0.05
    yaw_tolerance: float = 0.05

    def __post_init__(self) -> None:
        if self.xy_tolerance <= 0.0:
            raise ConfigError("control.goal_checker.xy_tolerance", "must be > 0")
        if self.yaw_tolerance <= 0.0:
            raise ConfigError("control.goal_checker.yaw_tolerance", "must be > 0")


class GoalChecker:
    def __init__(self, config: GoalCheckerConfig | None = None) -> None:
        self.config = config or GoalCheckerConfig()
        self._xy_reached = False

    @property
    def xy_reached(self) -> bool:
        """True once the position has been within tolerance (latched until :meth:`reset`)."""
        return self._xy_reached

    def position_reached(self, pose: Pose2D, goal: Pose2D) -> bool:
        """Check (and latch) the position part."""
        if not self._xy_reached and pose.distance_to(goal) <= self.config.xy_tolerance:
            self._xy_reached = True
        return self._xy_reached

    def latch(self) -> None:
        """Declare the position reached (the controller does so when it drives past the goal)."""
        self._xy_reached = True

    def is_reached(self, pose: Pose2D, goal: Pose2D) -> bool:
        """Position (latched) and heading both within tolerance."""
        return (
            self.position_reached(pose, goal)
            and abs(pose.heading_error_to(goal)) <= self.config.yaw_tolerance
        )

    def reset(self) -> None:
        self._xy_reached = False
