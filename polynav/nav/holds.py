"""Holds: an e-stop or lost localization stops the robot without ending its goal.

While held, the robot stands; when the cause goes the goal goes on with a fresh plan. A hold
that lasts ends the goal: lost localization after ``localization_grace``, an e-stop after
``estop_fail_after`` when that is set (by default an e-stop holds for ever: someone pressed it
and someone releases it).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

from polynav.nav.attempt import FailureReason
from polynav.nav.navigator_config import NavigatorConfig

log = logging.getLogger(__name__)

ESTOP = "e-stop"
LOCALIZATION_LOST = "localization lost"


@dataclass(frozen=True, slots=True)
class HoldStep:
    """What one control period of holds asks of the navigator."""

    held: bool = False  # stand still this period
    began: str | None = None  # a hold with this cause began: tell it
    released: str | None = None  # the hold with this cause ended: tell it, plan afresh
    expired: FailureReason | None = None  # the hold lasted too long: fail with this
    message: str = ""


class Hold:
    """The current hold of one goal, if any."""

    def __init__(self, config: NavigatorConfig) -> None:
        self._config = config
        self._cause: str | None = None
        self._since = 0.0

    def reset(self) -> None:
        self._cause = None

    def tick(self, now: float, *, estop: bool, lost: bool) -> HoldStep:
        cause = ESTOP if estop else LOCALIZATION_LOST if lost else None
        if cause is None:
            released, self._cause = self._cause, None
            if released is not None:
                log.info("navigation hold released (%s)", released)
            return HoldStep(released=released)
        began = None
        if self._cause != cause:
            log.warning("navigation held: %s", cause)
            began = self._cause = cause
            self._since = now
        held_for = now - self._since
        cfg = self._config
        if cause == LOCALIZATION_LOST and held_for >= cfg.localization_grace:
            return HoldStep(True, began, expired=FailureReason.LOCALIZATION_LOST,
                            message="localization lost for too long")
        if cause == ESTOP and cfg.estop_fail_after is not None and held_for >= cfg.estop_fail_after:
            return HoldStep(True, began, expired=FailureReason.ESTOP,
                            message="e-stop held for too long")
        return HoldStep(True, began)
