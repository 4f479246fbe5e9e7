"""What a path-following controller is, and what it answers each control period."""

from __future__ import annotations

import enum
from dataclasses import dataclass
from typing import Protocol

from polynav.geometry import Pose2D, Twist
from polynav.maps.interface import CostGrid
from polynav.planning.path import Path


class ControlStatus(enum.Enum):
    """How the controller sees its job after one period."""

    ROTATING = "rotating"  # turning in place toward the path or the goal heading
    TRACKING = "tracking"  # following the path
    SLOWING = "slowing"  # obstacle near the path ahead: reduced speed
    BLOCKED = "blocked"  # obstacle on the path ahead: stopped, a re-plan is wanted
    ARRIVED = "arrived"  # within the goal tolerances: stopped


@dataclass(frozen=True, slots=True)
class ControlCommand:
    twist: Twist
    status: ControlStatus


class Controller(Protocol):
    def set_path(self, path: Path, goal: Pose2D) -> None:
        """Follow ``path`` and finish at ``goal`` (its heading included)."""
        ...

    def compute(
        self, pose: Pose2D, velocity: Twist, costmap: CostGrid, dt: float
    ) -> ControlCommand:
        """The velocity to command for the next ``dt`` [s], given the robot's pose and velocity."""
        ...

    def set_goal_options(self, *, yaw_tolerance: float | None, reverse_allowed: bool) -> None:
        """Per-goal heading tolerance [rad] (``None``: the configured one) and whether the
        reversed goal heading is accepted; kept until set again (not cleared by reset)."""
        ...

    def reset(self) -> None:
        """Forget the path and the velocity history (after a cancel or a recovery)."""
        ...
