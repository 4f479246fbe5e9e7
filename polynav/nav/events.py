"""Events a navigation attempt emits, one per change, in the order they happen.

Every event carries the simulated or wall time ``stamp`` it happened at and the attempt snapshot
after the change, so a subscriber never has to query back.
"""

from __future__ import annotations

from dataclasses import dataclass

from polynav.localization.interface import PoseUncertainty
from polynav.nav.attempt import NavigationAttempt


@dataclass(frozen=True, slots=True)
class NavigationEvent:
    stamp: float
    attempt: NavigationAttempt


@dataclass(frozen=True, slots=True)
class NavigationStarted(NavigationEvent):
    pass


@dataclass(frozen=True, slots=True)
class PathPlanned(NavigationEvent):
    """A (re)plan succeeded; ``length`` [m] is the new path's length."""

    length: float = 0.0


@dataclass(frozen=True, slots=True)
class NavigationPaused(NavigationEvent):
    pass


@dataclass(frozen=True, slots=True)
class NavigationResumed(NavigationEvent):
    pass


@dataclass(frozen=True, slots=True)
class NavigationBlocked(NavigationEvent):
    """An obstacle stands on the path ahead; the robot waits, then re-plans."""


@dataclass(frozen=True, slots=True)
class NavigationWaiting(NavigationEvent):
    """The robot waits until its patience runs out: ``cause`` ``"person"``, only people block
    the way and it waits for them to make way ("please make way"), looking for another way
    meanwhile; ``"goal occupied"``, something not on the map stands on the goal
    (:mod:`~polynav.nav.goal_wait`)."""

    cause: str = "person"


@dataclass(frozen=True, slots=True)
class NavigationRetry(NavigationEvent):
    """A retry after a failure; ``cause`` says what failed and ``recovery`` what is tried."""

    cause: str = ""
    recovery: str = ""


@dataclass(frozen=True, slots=True)
class NavigationHeld(NavigationEvent):
    """Motion is held by an e-stop or lost localization; ``cause`` says which."""

    cause: str = ""


@dataclass(frozen=True, slots=True)
class NavigationReleased(NavigationEvent):
    """The hold ended; navigation continues."""

    cause: str = ""


@dataclass(frozen=True, slots=True)
class NavigationSucceeded(NavigationEvent):
    """The goal is reached; ``uncertainty`` says how well the robot knows it is there."""

    @property
    def uncertainty(self) -> PoseUncertainty | None:
        """The localization's uncertainty at arrival (``None``: the localizer gives none)."""
        return self.attempt.arrival_uncertainty


@dataclass(frozen=True, slots=True)
class NavigationFailed(NavigationEvent):
    pass


@dataclass(frozen=True, slots=True)
class NavigationCanceled(NavigationEvent):
    pass


@dataclass(frozen=True, slots=True)
class PlanFailed(NavigationEvent):
    """A global plan failed; ``cause``: ``"start_unknown"``, ``"start_occupied"``,
    ``"goal_occupied"``, ``"outside_map"``, ``"walled_in_unknown"`` (only unknown cells part
    the robot from the goal, with unknown-as-obstacle on: :mod:`polynav.nav.unknown_walls`) or
    ``"no_path"``. A retry or a failure follows."""

    cause: str = ""


@dataclass(frozen=True, slots=True)
class ChargerLeaveStarted(NavigationEvent):
    """The attempt begins on a charger: the robot backs straight off it first."""


@dataclass(frozen=True, slots=True)
class ChargerLeaveRetry(NavigationEvent):
    """No headway off the charger for ``undock_retry_after`` seconds; ``retries`` so far."""

    retries: int = 0


@dataclass(frozen=True, slots=True)
class ChargerLeft(NavigationEvent):
    pass


@dataclass(frozen=True, slots=True)
class ChargerLeaveFailed(NavigationEvent):
    pass


@dataclass(frozen=True, slots=True)
class DockingStarted(NavigationEvent):
    """The robot stands at the charger's approach and drives onto the contacts."""


@dataclass(frozen=True, slots=True)
class DockingSucceeded(NavigationEvent):
    pass


@dataclass(frozen=True, slots=True)
class DockingFailed(NavigationEvent):
    """``cause``: ``"no_feature"`` (no charger's plate seen near the marker),
    ``"no_infrared"`` (its beacon not seen), ``"bad_data"`` (contact, but the charger's data
    link gave no valid frame), ``"no_contact"`` (on the charger pose but no charging current)
    or ``"timeout"``."""

    cause: str = ""
