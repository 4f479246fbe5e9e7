"""A navigation attempt: one goal, its state, and why it ended.

The states are the ones every vendor dialect exposes in some form (Yunji ``move_status``, Galileo
``targetStatus``, androidmsg navigation status), so adapters map them once.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass

from polynav.geometry import Pose2D
from polynav.localization.interface import PoseUncertainty


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
    UNDOCK_FAILED = "undock failed"
    DOCK_FAILED = "dock failed"
    BLOCKED_BY_PERSON = "blocked by person"
    NOT_LOCALIZED = "not localized"
    DOOR_CLOSED = "door closed"


class Phase(enum.Enum):
    """What a running attempt is doing (vendors' detailed running status)."""

    LEAVE_CHARGER = "leave_charger"
    NAVIGATE = "navigate"
    DOCK = "dock"


#: Position uncertainty [m] a docking goal demands at its approach by default: the contacts
#: forgive a few centimetres across, and the straight drive onto them no more.
DOCK_POSITION_UNCERTAINTY = 0.05

#: What ``precise`` means where a dialect or the API has only a flag: within the goal checker's
#: usual 5 cm.
PRECISE_POSITION_UNCERTAINTY = 0.05


@dataclass(frozen=True, slots=True)
class GoalOptions:
    """How one goal is to be reached, beyond the navigator's defaults.

    Attributes:
        yaw_tolerance: accepted final heading error [rad] (else the controller's).
        reverse_allowed: the goal heading reversed (the robot's tail facing the goal's
            direction) is accepted too, for robots that dock either way.
        pass_tolerance: the goal is reached as soon as the robot comes this close [m], with
            no final turn (a waypoint passed on the way, as a patrol's points).
        near_tolerance: when the goal itself cannot be reached (occupied, walled off), ending
            within this distance [m] of it counts as success.
        max_retries: consecutive failures without progress before giving up (else the
            navigator's).
        undock_distance: the robot stands on a charger: back straight off it this far [m]
            before planning.
        dock: the goal is a charger's docking pose: drive to its approach, then dock onto it
            and wait for charging contact.
        goal_wait: how long [s] to wait for a goal held by something not on the map (else the
            navigator's ``goal_wait``); 0 fails it at once, for a caller with its own retries.
        max_position_uncertainty: a precise arrival: the localization's position uncertainty
            [m] (one standard deviation) must be within this at arrival, else the attempt fails
            ``not localized`` rather than claim a pose the scan cannot see. A docking goal
            demands :data:`DOCK_POSITION_UNCERTAINTY` when this is not given.
    """

    yaw_tolerance: float | None = None
    reverse_allowed: bool = False
    pass_tolerance: float | None = None
    near_tolerance: float | None = None
    max_retries: int | None = None
    undock_distance: float | None = None
    dock: bool = False
    goal_wait: float | None = None
    max_position_uncertainty: float | None = None

    def __post_init__(self) -> None:
        for key in ("yaw_tolerance", "pass_tolerance", "near_tolerance", "undock_distance",
                    "max_position_uncertainty"):
            value = getattr(self, key)
            if value is not None and not value > 0.0:
                raise ValueError(f"{key} must be > 0, got {value}")
        if self.goal_wait is not None and not self.goal_wait >= 0.0:
            raise ValueError(f"goal_wait must be >= 0, got {self.goal_wait}")
        if self.max_retries is not None and self.max_retries < 0:
            raise ValueError(f"max_retries must be >= 0, got {self.max_retries}")

    @property
    def required_position_uncertainty(self) -> float | None:
        """The position uncertainty [m] an arrival must be within, or ``None`` (any)."""
        if self.max_position_uncertainty is not None:
            return self.max_position_uncertainty
        return DOCK_POSITION_UNCERTAINTY if self.dock else None


@dataclass(frozen=True, slots=True)
class NavigationAttempt:
    """A snapshot of one attempt. ``distance_travelled`` [m] counts the robot's own motion;
    ``arrival_uncertainty`` is the localization's uncertainty when the robot arrived (``None``
    before, or when the localizer gives none)."""

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
    phase: Phase = Phase.NAVIGATE
    plans: int = 0
    options: GoalOptions = GoalOptions()
    arrival_uncertainty: PoseUncertainty | None = None
