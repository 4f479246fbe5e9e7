"""Is the robot getting anywhere? The navigator's "stuck" detector (Nav2 ``SimpleProgressChecker``).

The robot makes progress when it leaves a circle of ``required_movement_radius`` around the pose
where the check last restarted; failing to do so for ``movement_time_allowance`` seconds means it is
stuck. Turning in place does not count as progress: the navigator only consults the checker while
the controller says it is driving along the path, so a long turn toward a goal heading is never
mistaken for being stuck.
"""

from __future__ import annotations

from dataclasses import dataclass

from polynav.errors import ConfigError
from polynav.geometry import Pose2D


@dataclass(frozen=True, slots=True)
class ProgressCheckerConfig:
    required_movement_radius: float = 0.5
    movement_time_allowance: float = 10.0

    def __post_init__(self) -> None:
        if self.required_movement_radius <= 0.0:
            raise ConfigError("control.progress_checker.required_movement_radius", "must be > 0")
        if self.movement_time_allowance <= 0.0:
            raise ConfigError("control.progress_checker.movement_time_allowance", "must be > 0")


class ProgressChecker:
    def __init__(self, config: ProgressCheckerConfig | None = None) -> None:
        self.config = config or ProgressCheckerConfig()
        self._reference: Pose2D | None = None
        self._since = 0.0

    def reset(self, pose: Pose2D, now: float) -> None:
        """Restart the check from ``pose`` at time ``now`` [s]."""
        self._reference = pose
        self._since = now

    def check(self, pose: Pose2D, now: float) -> bool:
        """False once the robot has stayed near the reference pose for too long."""
        if self._reference is None:
            self.reset(pose, now)
            return True
        if pose.distance_to(self._reference) >= self.config.required_movement_radius:
            self.reset(pose, now)
            return True
        return now - self._since < self.config.movement_time_allowance
