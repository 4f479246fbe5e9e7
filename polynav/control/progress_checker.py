"""Is the robot getting anywhere? The navigator's "stuck" detector.

After Nav2's ``PoseProgressChecker``: the robot makes progress when it leaves a circle of
``required_movement_radius`` around the reference pose, *or* when its heading turns
``required_movement_angle`` away from the reference heading. Either restarts the check from the
current pose; failing both for ``movement_time_allowance`` seconds means it is stuck.

Why turning counts: the controller turns in place at the start (toward the path) and at the end
(to the goal heading), for up to half a turn each time. A robot doing that is doing its job, and a
checker that only looked at position would call a slow final turn "stuck". What does not count is
dithering: swaying back and forth by less than the angle, or creeping within the circle, never
moves the reference, so a robot that only wobbles in place is still declared stuck. The price is
that a robot spinning endlessly on the spot is never declared stuck; the controller never commands
that (each turn in place ends on a heading), so it is not a failure this checker needs to catch.

Time is the ``now`` [s] of the caller's clock (simulated or wall), never read here.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

from polynav.errors import ConfigError
from polynav.geometry import Pose2D

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True)
class ProgressCheckerConfig:
    """How far [m] or how much turn [rad] counts as progress, and how long [s] it may take.

    ``required_movement_angle`` of ``math.inf`` makes turning never count (Nav2's
    ``SimpleProgressChecker``).
    """

    required_movement_radius: float = 0.5
    movement_time_allowance: float = 10.0
    required_movement_angle: float = 0.5

    def __post_init__(self) -> None:
        if not self.required_movement_radius > 0.0:
            raise ConfigError("control.progress_checker.required_movement_radius", "must be > 0")
        if not self.movement_time_allowance > 0.0:
            raise ConfigError("control.progress_checker.movement_time_allowance", "must be > 0")
        if not self.required_movement_angle > 0.0:
            raise ConfigError("control.progress_checker.required_movement_angle", "must be > 0")
        if math.isfinite(self.required_movement_angle) and self.required_movement_angle > math.pi:
            raise ConfigError(
                "control.progress_checker.required_movement_angle",
                "must be <= pi (a heading is never farther), or inf to ignore turning",
            )


class ProgressChecker:
    """Stuck detection against a reference pose that moves on whenever the robot does."""

    def __init__(self, config: ProgressCheckerConfig | None = None) -> None:
        self.config = config or ProgressCheckerConfig()
        self._reference: Pose2D | None = None
        self._since = 0.0

    def reset(self, pose: Pose2D, now: float) -> None:
        """Restart the check from ``pose`` at time ``now`` [s]."""
        self._reference = pose
        self._since = now

    def check(self, pose: Pose2D, now: float) -> bool:
        """False once the robot has made no progress for ``movement_time_allowance`` [s].

        The first call after construction starts the clock at ``pose``.
        """
        if self._reference is None:
            self.reset(pose, now)
            return True
        cfg = self.config
        moved = pose.distance_to(self._reference) >= cfg.required_movement_radius
        turned = abs(self._reference.heading_error_to(pose)) >= cfg.required_movement_angle
        if moved or turned:
            self.reset(pose, now)
            return True
        if now - self._since >= cfg.movement_time_allowance:
            log.debug("no progress for %.1f s from (%.2f, %.2f)", now - self._since,
                      self._reference.x, self._reference.y)
            return False
        return True
