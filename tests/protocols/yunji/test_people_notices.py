"""People in the way reach a Yunji client as the blocked notice (01204), and a goal they never
free fails as a plain move failure (01003), not as stuck (01006) or unreachable (01007)."""

from __future__ import annotations

from polynav.geometry import Pose2D
from polynav.nav.attempt import FailureReason
from polynav.protocols.yunji.events import NotificationMapper
from polynav.runtime import events


def _mapper() -> NotificationMapper:
    mapper = NotificationMapper(lambda attempt_id: None, estop_active=False)
    mapper.map(events.NavigationStarted(0.0, 7, Pose2D(1.0, 2.0, 0.0), "kitchen"))
    return mapper


def test_waiting_for_people_is_the_blocked_notice_with_the_target() -> None:
    notes = _mapper().map(events.NavigationWaiting(3.0, 7, "person"))
    assert [(n.code, n.data) for n in notes] == [("01204", {"target": "kitchen"})]


def test_a_goal_people_never_freed_ends_with_01003_only() -> None:
    reason = FailureReason.BLOCKED_BY_PERSON.value
    notes = _mapper().map(events.NavigationFailed(63.0, 7, reason, 4.0, True))
    assert [n.code for n in notes] == ["01003"]
    assert notes[0].data == {"target": "kitchen", "distance": 4.0}
