"""Missions: queued, claimed oldest first by one robot at a time, requeued in their place,
finished; on SQLite and PostgreSQL alike."""

from __future__ import annotations

import pytest

from polynav.errors import Conflict, InvalidRequest, NotFound
from polynav.fleet.records import FleetRecords, MissionState

A = [{"point": "lobby"}]
B = [{"point": "lab", "map": "floor1"}, {"point": "office", "map": "floor3"}]


def test_add_mission_queues_it_with_its_stops_in_order(records: FleetRecords) -> None:
    added = records.add_mission(B, now=1.0, mission_id="m1")
    assert added.mission_id == "m1"
    assert added.state is MissionState.QUEUED
    assert added.stops == ({"point": "lab", "map": "floor1"},
                           {"point": "office", "map": "floor3"})
    assert (added.robot, added.created, added.updated, added.attempts) == (None, 1.0, 1.0, 0)
    assert records.mission("m1") == added


def test_add_mission_without_id_names_it(records: FleetRecords) -> None:
    first = records.add_mission(A, now=1.0)
    second = records.add_mission(A, now=1.0)
    assert first.mission_id != second.mission_id
    assert [m.mission_id for m in records.missions()] == [first.mission_id, second.mission_id]


def test_adding_the_same_mission_again_returns_it_and_other_stops_conflict(
        records: FleetRecords) -> None:
    first = records.add_mission(A, now=1.0, mission_id="m1")
    assert records.add_mission(A, now=5.0, mission_id="m1") == first
    with pytest.raises(Conflict):
        records.add_mission(B, now=5.0, mission_id="m1")
    assert len(records.missions()) == 1


def test_claims_take_the_oldest_queued_mission_first(records: FleetRecords) -> None:
    records.add_mission(A, now=3.0, mission_id="late")
    records.add_mission(A, now=1.0, mission_id="early")
    records.add_mission(A, now=2.0, mission_id="middle")
    got = [records.claim_mission(robot, now=4.0) for robot in ("r1", "r2", "r3", "r4")]
    assert [m.mission_id if m else None for m in got] == ["early", "middle", "late", None]
    assert [m.robot for m in got if m] == ["r1", "r2", "r3"]
    assert all(m.state is MissionState.ACTIVE and m.attempts == 1 for m in got if m)


def test_a_robot_with_an_active_mission_gets_that_one_again(records: FleetRecords) -> None:
    records.add_mission(A, now=1.0, mission_id="m1")
    records.add_mission(A, now=2.0, mission_id="m2")
    first = records.claim_mission("r1", now=3.0)
    again = records.claim_mission("r1", now=4.0)
    assert first is not None and again == first
    assert records.mission("m2").state is MissionState.QUEUED


def test_claim_with_nothing_queued_is_none(records: FleetRecords) -> None:
    assert records.claim_mission("r1", now=1.0) is None


def test_a_requeued_mission_keeps_its_place_and_counts_attempts(records: FleetRecords) -> None:
    records.add_mission(A, now=1.0, mission_id="m1")
    records.add_mission(A, now=2.0, mission_id="m2")
    records.claim_mission("r1", now=3.0)
    assert records.requeue_mission("m1", now=4.0) is True
    back = records.mission("m1")
    assert (back.state, back.robot, back.updated) == (MissionState.QUEUED, None, 4.0)
    again = records.claim_mission("r2", now=5.0)
    assert again is not None
    assert (again.mission_id, again.robot, again.attempts) == ("m1", "r2", 2)


def test_requeue_robot_puts_its_mission_back_and_nothing_else(records: FleetRecords) -> None:
    records.add_mission(A, now=1.0, mission_id="m1")
    records.add_mission(A, now=2.0, mission_id="m2")
    records.claim_mission("r1", now=3.0)
    records.claim_mission("r2", now=3.0)
    assert records.requeue_robot("r1", now=4.0) == ("m1",)
    assert records.requeue_robot("r1", now=4.0) == ()
    assert records.mission("m1").state is MissionState.QUEUED
    assert records.mission("m2").robot == "r2"


def test_requeue_of_a_mission_not_active_changes_nothing(records: FleetRecords) -> None:
    records.add_mission(A, now=1.0, mission_id="m1")
    assert records.requeue_mission("m1", now=2.0) is False
    assert records.mission("m1").updated == 1.0
    with pytest.raises(NotFound):
        records.requeue_mission("nope", now=2.0)


def test_finish_ends_an_active_mission_once(records: FleetRecords) -> None:
    records.add_mission(A, now=1.0, mission_id="m1")
    records.claim_mission("r1", now=2.0)
    done = records.finish_mission("m1", now=3.0)
    assert (done.state, done.robot, done.updated) == (MissionState.DONE, "r1", 3.0)
    assert records.finish_mission("m1", now=9.0) == done
    with pytest.raises(Conflict):
        records.finish_mission("m1", now=9.0, failed=True)
    assert records.claim_mission("r1", now=4.0) is None  # free again, and nothing queued


def test_finish_of_a_queued_or_unknown_mission_is_refused(records: FleetRecords) -> None:
    records.add_mission(A, now=1.0, mission_id="m1")
    with pytest.raises(Conflict):
        records.finish_mission("m1", now=2.0)
    with pytest.raises(NotFound):
        records.finish_mission("nope", now=2.0)


def test_a_failed_mission_is_listed_by_state(records: FleetRecords) -> None:
    records.add_mission(A, now=1.0, mission_id="m1")
    records.add_mission(A, now=2.0, mission_id="m2")
    records.claim_mission("r1", now=3.0)
    records.finish_mission("m1", now=4.0, failed=True)
    assert [m.mission_id for m in records.missions(MissionState.FAILED)] == ["m1"]
    assert [m.mission_id for m in records.missions(MissionState.QUEUED)] == ["m2"]


@pytest.mark.parametrize(("stops", "field"), [
    ([], "stops"),
    ("lobby", "stops"),
    ([{"map": "floor1"}], "stops[0].point"),
    ([{"point": ""}], "stops[0].point"),
    (["lobby"], "stops[0]"),
    ([{"point": "a", "speed": object()}], "stops"),
    ([{"point": "a", "speed": float("nan")}], "stops"),
])
def test_bad_stops_are_refused_by_field(records: FleetRecords, stops: object,
                                        field: str) -> None:
    with pytest.raises(InvalidRequest) as caught:
        records.add_mission(stops, now=1.0)  # type: ignore[arg-type]
    assert caught.value.field == field
    assert records.missions() == ()


@pytest.mark.parametrize("now", [float("nan"), float("inf"), "1", None, True])
def test_bad_times_are_refused(records: FleetRecords, now: object) -> None:
    with pytest.raises(InvalidRequest):
        records.add_mission(A, now=now)  # type: ignore[arg-type]
    with pytest.raises(InvalidRequest):
        records.claim_mission("r1", now=now)  # type: ignore[arg-type]
