"""A mission requeued when its robot was lost is resumed by that robot when it comes back still
doing it, on the same attempt, unless another robot has claimed it meanwhile; on SQLite and
PostgreSQL alike."""

from __future__ import annotations

import pytest

from polynav.errors import NotFound
from polynav.fleet.records import FleetRecords, MissionState

A = [{"point": "lobby"}]


def test_a_requeued_mission_is_resumed_by_its_robot_on_the_same_attempt(
        records: FleetRecords) -> None:
    records.add_mission(A, now=1.0, mission_id="m1")
    records.claim_mission("r1", now=2.0)
    assert records.requeue_robot("r1", now=3.0) == ("m1",)
    resumed = records.resume_mission("m1", "r1", now=4.0)
    assert resumed is not None
    assert (resumed.state, resumed.robot, resumed.attempts) == (MissionState.ACTIVE, "r1", 1)
    assert [e.what for e in records.audit()][-2:] == ["mission.requeued", "mission.resumed"]
    # A robot does one mission at a time; a resumed mission is no longer queued.
    assert records.claim_mission("r1", now=5.0) == resumed
    assert records.resume_mission("m1", "r2", now=5.0) is None


def test_a_mission_claimed_by_another_robot_or_cancelled_is_not_resumed(
        records: FleetRecords) -> None:
    records.add_mission(A, now=1.0, mission_id="m1")
    records.add_mission(A, now=1.0, mission_id="m2")
    records.claim_mission("r1", now=2.0)
    records.requeue_robot("r1", now=3.0)
    taken = records.claim_mission("r2", now=4.0)
    assert taken is not None and taken.mission_id == "m1"
    assert records.resume_mission("m1", "r1", now=5.0) is None
    records.cancel_mission("m2", now=5.0)
    assert records.resume_mission("m2", "r1", now=6.0) is None
    assert records.mission("m1").robot == "r2"
    with pytest.raises(NotFound):
        records.resume_mission("nope", "r1", now=6.0)
