"""Has the robot reached its goal? Position first, then heading, with a latch on the position.

Like Nav2's ``SimpleGoalChecker`` with ``stateful: true``: once the position has been within
``xy_tolerance`` the checker remembers it, so that the centimetre or two a localization estimate
jitters while the robot turns in place to the goal heading cannot send it back to driving (which
would make it dance around the goal, each small move causing more jitter). Only the heading is
checked after that, until :meth:`GoalChecker.reset`.
"""

from __future__ import annotations

import logging

from polynav.errors import ConfigError
from polynav.geometry import Pose2D

log = logging.getLogger(__name__)


class GoalChecker:
    """Stateful goal check: a latched position test and a live heading test."""

    def __init__(self, xy_tolerance: float = 0.05, yaw_tolerance: float = 0.05) -> None:
        """
        Args:
            xy_tolerance: accepted distance [m] from the goal position.
            yaw_tolerance: accepted heading error [rad].

        Raises:
            ConfigError: a tolerance that is not positive.
        """
        if not xy_tolerance > 0.0:
            raise ConfigError("control.goal_checker.xy_tolerance", "must be > 0")
        if not yaw_tolerance > 0.0:
            raise ConfigError("control.goal_checker.yaw_tolerance", "must be > 0")
        self.xy_tolerance = xy_tolerance
        self.yaw_tolerance = yaw_tolerance
        self._xy_reached = False

    @property
    def xy_reached(self) -> bool:
        """True once the position has been reached (latched until :meth:`reset`)."""
        return self._xy_reached

    def latch(self) -> None:
        """Declare the position reached.

        The controller calls this when it decides to stop translating, which it may do a little
        before the checker would see the position within tolerance on its own (it aims inside the
        tolerance, and stops when the goal is abeam).
        """
        if not self._xy_reached:
            log.debug("goal position reached")
        self._xy_reached = True

    def position_reached(self, pose: Pose2D, goal: Pose2D) -> bool:
        """Check and latch the position part: within ``xy_tolerance`` now or at any time before."""
        if not self._xy_reached and pose.distance_to(goal) <= self.xy_tolerance:
            self.latch()
        return self._xy_reached

    def heading_reached(self, pose: Pose2D, goal: Pose2D) -> bool:
        """The heading part, never latched: within ``yaw_tolerance`` now."""
        return abs(pose.heading_error_to(goal)) <= self.yaw_tolerance

    def is_reached(self, pose: Pose2D, goal: Pose2D) -> bool:
        """Position (latched) and heading (now) both within tolerance."""
        return self.position_reached(pose, goal) and self.heading_reached(pose, goal)

    def reset(self) -> None:
        """Forget the latch (a new goal, or the robot was moved away from this one)."""
        self._xy_reached = False
