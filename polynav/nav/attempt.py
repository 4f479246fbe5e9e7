"""A navigation attempt: one goal, its state, and why it ended.

The states are the ones every vendor dialect exposes in some form (Yunji ``move_status``, Galileo
``targetStatus``, androidmsg navigation status), so adapters map them once.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass

from polynav.geometry import Pose2D


class NavigationState(enum.Enum):
    IDLE = "idle"
    RUNNING = "running"
    PAUSED = "paused"
    SUCCEEDED = "succeeded"
    FAILED = "failed"
    CANCELED = "canceled"

    @property
    def finished(self) -> bool:
        return self in (NavigationState.SUCCEEDED, NavigationState.FAILED, NavigationState.CANCELED)


class FailureReason(enum.Enum):
    """Why an attempt failed; each dialect maps these once, in its ``errors.py``."""

    NO_PATH = "no path"
    GOAL_OCCUPIED = "goal occupied"
    STUCK = "stuck"
    LOCALIZATION_LOST = "localization lost"
    ESTOP = "e-stop"


@dataclass(frozen=True, slots=True)
class NavigationAttempt:
    """A snapshot of one attempt. ``distance_travelled`` [m] counts the robot's own motion."""

    attempt_id: int
    goal: Pose2D
    state: NavigationState
    started_at: float
    ended_at: float | None = None
    reason: FailureReason | None = None
    message: str = ""
    retries: int = 0
    distance_travelled: float = 0.0
    distance_remaining: float | None = None
