"""A precise goal the robot reached without a pose it could vouch for reaches a Yunji client as
"maybe lost" (02010) and the move failure (01003)."""

from __future__ import annotations

from polynav.geometry import Pose2D
from polynav.nav.attempt import FailureReason
from polynav.protocols.yunji.events import NotificationMapper
from polynav.runtime import events


def _mapper() -> NotificationMapper:
    mapper = NotificationMapper(lambda attempt_id: None, estop_active=False)
    mapper.map(events.NavigationStarted(0.0, 7, Pose2D(1.0, 2.0, 0.0), "dock_1"))
    return mapper


def test_a_goal_failed_not_localized_sends_maybe_lost_then_the_move_failure() -> None:
    reason = FailureReason.NOT_LOCALIZED.value
    notes = _mapper().map(events.NavigationFailed(40.0, 7, reason, 25.0, True))
    assert [n.code for n in notes] == ["02010", "01003"]
    assert notes[1].data == {"target": "dock_1", "distance": 25.0}


def test_a_success_stays_the_documented_01002_with_target_and_distance() -> None:
    notes = _mapper().map(events.NavigationSucceeded(40.0, 7, 25.0, position_uncertainty=0.24,
                                                     heading_uncertainty=0.01))
    assert [(n.code, n.data) for n in notes] == [
        ("01002", {"target": "dock_1", "distance": 25.0})]
