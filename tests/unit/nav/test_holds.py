"""Holds on their own: told once when they begin and end, failing only when they last."""

from __future__ import annotations

from polynav.nav.attempt import FailureReason
from polynav.nav.holds import ESTOP, LOCALIZATION_LOST, Hold, HoldStep
from polynav.nav.navigator_config import NavigatorConfig


def test_a_hold_is_told_when_it_begins_and_when_it_ends_and_not_in_between() -> None:
    hold = Hold(NavigatorConfig())
    assert hold.tick(0.0, estop=False, lost=False) == HoldStep()
    assert hold.tick(1.0, estop=True, lost=False) == HoldStep(True, began=ESTOP)
    assert hold.tick(2.0, estop=True, lost=True) == HoldStep(True)  # the e-stop comes first
    assert hold.tick(500.0, estop=True, lost=False) == HoldStep(True)  # holds for ever
    assert hold.tick(501.0, estop=False, lost=False) == HoldStep(released=ESTOP)
    assert hold.tick(502.0, estop=False, lost=False) == HoldStep()


def test_lost_localization_fails_after_the_grace_and_a_long_e_stop_when_asked_to() -> None:
    hold = Hold(NavigatorConfig(localization_grace=5.0, estop_fail_after=10.0))
    assert hold.tick(0.0, estop=False, lost=True) == HoldStep(True, began=LOCALIZATION_LOST)
    assert hold.tick(4.9, estop=False, lost=True).expired is None
    step = hold.tick(5.0, estop=False, lost=True)
    assert step.expired is FailureReason.LOCALIZATION_LOST and step.held
    # A new cause starts its own clock.
    assert hold.tick(6.0, estop=True, lost=False) == HoldStep(True, began=ESTOP)
    assert hold.tick(15.9, estop=True, lost=False).expired is None
    assert hold.tick(16.0, estop=True, lost=False).expired is FailureReason.ESTOP
    hold.reset()
    assert hold.tick(17.0, estop=False, lost=False) == HoldStep()  # nothing to release
