"""The fleet manager over the in-process transport, with robots scripted at their end of it
and its records in SQLite: dispatch, outcomes, re-sending, lost robots, leases."""

from __future__ import annotations

import logging
from collections.abc import Iterator
from pathlib import Path

import pytest

from polynav.errors import InvalidRequest, NotFound
from polynav.fleet import messages as m
from polynav.fleet.manager import FleetManager, FleetManagerConfig
from polynav.fleet.records import FleetRecords, MissionState
from polynav.fleet.transport import InProcessTransport
from polynav.leases.book import LeaseBookConfig
from tests.helpers.scripted_vehicle import POINTS, Robot, Site


@pytest.fixture
def records(tmp_path: Path) -> Iterator[FleetRecords]:
    with FleetRecords.open(f"sqlite:///{tmp_path / 'fleet.db'}", name="fm1") as opened:
        yield opened


@pytest.fixture
def transport() -> InProcessTransport:
    return InProcessTransport()


def manager(transport: InProcessTransport, records: FleetRecords) -> FleetManager:
    return FleetManager(transport, records, Site(), levels={"floor1": 1, "floor2": 2},
                        leases=LeaseBookConfig(max_wait=50.0),
                        config=FleetManagerConfig(resend_after=2.0, max_sends=3,
                                                  max_attempts=2, dispatch_period=0.5,
                                                  lost_grace=1.0))


def online(transport: InProcessTransport, fm: FleetManager,
           *robots: tuple[str, float]) -> list[Robot]:
    out = [Robot(transport, serial, x) for serial, x in robots]
    for robot in out:
        robot.connection(m.ConnectionState.ONLINE)
    fm.tick(0.0)
    for robot in out:
        robot.state()
    fm.tick(0.1)
    return out


def test_a_mission_goes_to_the_nearest_robot_and_is_done_when_its_order_is(
        transport: InProcessTransport, records: FleetRecords) -> None:
    fm = manager(transport, records)
    far, near = online(transport, fm, ("far", -20.0), ("near", 8.0))
    mission = fm.submit([{"point": "desk", "map": "floor1"}], mission_id="m1")
    assert mission.state is MissionState.QUEUED
    fm.tick(1.0)
    assert far.order_ids() == []
    assert near.order_ids() == ["m1-1"]
    assert fm.robot("near").mission == "m1"
    near.state("m1-1", nodes=1)
    fm.tick(1.2)
    assert records.order("m1-1", 0).state.value == "confirmed"
    near.state("m1-1", nodes=0)
    fm.tick(1.4)
    assert fm.mission("m1").state is MissionState.DONE
    assert fm.robot("near").mission is None
    kinds = [e.kind for e in fm.events_after(0) if e.detail.get("mission") == "m1"]
    assert kinds == ["mission.queued", "mission.dispatched", "mission.started", "mission.done"]


def test_an_unconfirmed_order_is_resent_unchanged_then_given_up(
        transport: InProcessTransport, records: FleetRecords) -> None:
    fm = manager(transport, records)
    (robot,) = online(transport, fm, ("r1", 0.0))
    fm.submit([{"point": "desk", "map": "floor1"}], mission_id="m1")
    fm.tick(1.0)
    assert robot.order_ids() == ["m1-1"]
    fm.tick(2.5)
    assert robot.order_ids() == []  # not yet resend_after
    fm.tick(3.5)
    assert robot.order_ids() == ["m1-1"]
    assert records.order("m1-1", 0).sends == 2
    fm.tick(6.0)
    assert robot.order_ids() == ["m1-1"]
    # Sent max_sends times and never confirmed: the attempt failed, the mission requeued and
    # claimed again (a new order id, so the robot would not ignore it).
    fm.tick(8.5)
    assert fm.mission("m1").attempts == 2
    assert robot.order_ids() == ["m1-2"]


def test_a_failed_order_requeues_its_mission_until_max_attempts_then_fails_it(
        transport: InProcessTransport, records: FleetRecords) -> None:
    fm = manager(transport, records)
    r1, r2 = online(transport, fm, ("r1", 9.0), ("r2", 0.0))
    fm.submit([{"point": "desk", "map": "floor1"}], mission_id="m1")
    fm.tick(1.0)
    assert r1.order_ids() == ["m1-1"]
    r1.state("m1-1", nodes=1, failed=True)
    fm.tick(1.2)
    assert fm.mission("m1").state is MissionState.QUEUED
    fm.tick(1.6)  # r1 still reports its failed order (not busy): the nearest again
    assert r1.order_ids() == ["m1-2"]
    r1.state("m1-2", nodes=0, failed=True)
    fm.tick(1.8)
    failed = fm.mission("m1")
    assert (failed.state, failed.attempts, failed.robot) == (MissionState.FAILED, 2, "r1")
    assert r2.order_ids() == []


def test_a_lost_robot_loses_its_leases_and_its_mission_goes_to_another(
        transport: InProcessTransport, records: FleetRecords) -> None:
    fm = manager(transport, records)
    r1, r2 = online(transport, fm, ("r1", 9.0), ("r2", 0.0))
    fm.submit([{"point": "desk", "map": "floor1"}], mission_id="m1")
    fm.tick(1.0)
    assert r1.order_ids() == ["m1-1"]
    r1.state("m1-1", nodes=1)
    r1.ask("lift:A")
    fm.tick(1.2)
    assert r1.grants() == [m.GrantType.GRANTED]
    assert [(lease.resource, lease.holder) for lease in fm.live_leases()] == [
        ("lift:A", "r1")]
    r2.ask("lift:A")
    fm.tick(1.3)
    assert r2.grants() == [m.GrantType.QUEUED]
    r1.connection(m.ConnectionState.CONNECTIONBROKEN)  # its last will
    fm.tick(1.4)
    assert fm.robot("r1").connection == "CONNECTIONBROKEN"
    # The lift goes to the robot waiting for it, the mission to the robot still online.
    assert r2.grants() == [m.GrantType.GRANTED]
    assert [(lease.resource, lease.holder) for lease in fm.live_leases()] == [
        ("lift:A", "r2")]
    fm.tick(1.6)
    # The mission waits lost_grace for its robot to come back still doing it; then it goes.
    assert r2.order_ids() == [] and fm.mission("m1").state is MissionState.QUEUED
    fm.tick(2.5)
    assert r2.order_ids() == ["m1-2"]
    r2.state("m1-2", nodes=0)
    fm.tick(2.7)
    done = fm.mission("m1")
    assert (done.state, done.robot, done.attempts) == (MissionState.DONE, "r2", 2)
    whats = [e.what for e in records.audit()]
    assert "lease.released" in whats and "mission.requeued" in whats
    # Back online, the lost robot is asked for its state; still driving the order it no
    # longer owns, it is told to drop it.
    r1.actions.drain()
    r1.connection(m.ConnectionState.ONLINE)
    fm.tick(3.0)
    assert action_kinds(r1) == ["stateRequest"]
    r1.state("m1-1", nodes=1)
    fm.tick(3.2)
    assert action_kinds(r1) == ["cancelOrder"]
    assert fm.mission("m1").robot == "r2"


def action_kinds(robot: Robot) -> list[str]:
    return [a.action_type for msg in robot.actions.drain() if isinstance(msg, m.InstantActions)
            for a in msg.actions]


def test_a_robot_back_still_driving_its_requeued_mission_resumes_it(
        transport: InProcessTransport, records: FleetRecords) -> None:
    # A restarted broker delivers every robot's will while the robots drive on.
    fm = manager(transport, records)
    r1, r2 = online(transport, fm, ("r1", 9.0), ("r2", 0.0))
    fm.submit([{"point": "desk", "map": "floor1"}], mission_id="m1")
    fm.tick(1.0)
    assert r1.order_ids() == ["m1-1"]
    r1.state("m1-1", nodes=1)
    fm.tick(1.2)
    for robot in (r1, r2):
        robot.connection(m.ConnectionState.CONNECTIONBROKEN)
    fm.tick(1.4)
    assert fm.mission("m1").state is MissionState.QUEUED
    for robot in (r1, r2):
        robot.connection(m.ConnectionState.ONLINE)
        robot.actions.drain()
    fm.tick(1.6)  # back, but no state since: m1 waits for r1's word, given to no one
    assert fm.mission("m1").state is MissionState.QUEUED
    r2.state()
    fm.tick(1.8)
    assert r2.order_ids() == [] and fm.mission("m1").state is MissionState.QUEUED
    r1.state("m1-1", nodes=1)
    fm.tick(2.0)
    resumed = fm.mission("m1")
    assert (resumed.state, resumed.robot, resumed.attempts) == (MissionState.ACTIVE, "r1", 1)
    assert "cancelOrder" not in action_kinds(r1) and r1.order_ids() == []
    assert fm.robot("r1").mission == "m1"
    r1.state("m1-1", nodes=0)
    fm.tick(2.2)
    done = fm.mission("m1")
    assert (done.state, done.robot, done.attempts) == (MissionState.DONE, "r1", 1)
    kinds = [e.kind for e in fm.events_after(0) if e.detail.get("mission") == "m1"]
    assert kinds == ["mission.queued", "mission.dispatched", "mission.started",
                     "mission.requeued", "mission.resumed", "mission.done"]


def test_a_robot_back_without_its_order_leaves_the_mission_to_the_queue(
        transport: InProcessTransport, records: FleetRecords) -> None:
    fm = manager(transport, records)
    (r1,) = online(transport, fm, ("r1", 9.0))
    fm.submit([{"point": "desk", "map": "floor1"}], mission_id="m1")
    fm.tick(1.0)
    r1.state("m1-1", nodes=1)
    fm.tick(1.2)
    r1.connection(m.ConnectionState.CONNECTIONBROKEN)
    fm.tick(1.4)
    r1.connection(m.ConnectionState.ONLINE)
    r1.order_ids()
    fm.tick(1.6)
    r1.state()  # restarted: no order; the mission is not held for it any longer
    fm.tick(1.8)
    fm.tick(2.2)
    again = fm.mission("m1")
    assert (again.state, again.robot, again.attempts) == (MissionState.ACTIVE, "r1", 2)
    assert r1.order_ids() == ["m1-2"]


def test_two_managers_on_one_database_never_grant_one_lift_twice(
        tmp_path: Path) -> None:
    url = f"sqlite:///{tmp_path / 'shared.db'}"
    with FleetRecords.open(url, name="fm1") as rec1, FleetRecords.open(url, name="fm2") as rec2:
        t1, t2 = InProcessTransport(), InProcessTransport()
        fm1, fm2 = manager(t1, rec1), manager(t2, rec2)
        (a,) = online(t1, fm1, ("a", 0.0))
        (b,) = online(t2, fm2, ("b", 0.0))
        a.ask("lift:A")
        b.ask("lift:A")
        fm1.tick(1.0)
        fm2.tick(1.0)
        assert a.grants() == [m.GrantType.GRANTED]
        assert b.grants() == [m.GrantType.QUEUED]  # its own book was free: the records said no
        a.transport.publish(m.topic("a", m.ZoneRequest), m.ZoneRequest(
            9, "a", "rel", "lift:A", m.ZoneRequestType.RELEASE))
        fm1.tick(2.0)
        fm2.tick(2.0)  # asked again at its tick, now granted
        assert b.grants() == [m.GrantType.GRANTED]
        assert [(lease.holder) for lease in rec1.live_leases(2.0)] == ["b"]


def test_bad_missions_are_refused_naming_the_stop(
        transport: InProcessTransport, records: FleetRecords) -> None:
    fm = manager(transport, records)
    with pytest.raises(NotFound, match="floor1/nowhere"):
        fm.submit([{"point": "nowhere", "map": "floor1"}])
    with pytest.raises(InvalidRequest, match=r"stops\[1\].map"):
        fm.submit([{"point": "desk", "map": "floor1"}, {"point": "ward"}])
    with pytest.raises(InvalidRequest, match="at least one stop"):
        fm.submit([])
    assert fm.missions() == ()


def test_a_cancelled_mission_is_not_dispatched_and_an_active_one_cancels_its_order(
        transport: InProcessTransport, records: FleetRecords) -> None:
    fm = manager(transport, records)
    fm.submit([{"point": "desk", "map": "floor1"}], mission_id="queued")
    assert fm.cancel("queued").state is MissionState.CANCELLED
    (robot,) = online(transport, fm, ("r1", 0.0))
    fm.submit([{"point": "ward", "map": "floor2"}], mission_id="m2")
    fm.tick(1.0)
    assert robot.order_ids() == ["m2-1"]
    robot.actions.drain()
    assert fm.cancel("m2").state is MissionState.CANCELLED
    kinds = [a.action_type for msg in robot.actions.drain()
             if isinstance(msg, m.InstantActions) for a in msg.actions]
    assert kinds == ["cancelOrder"]


def test_malformed_connection_messages_are_logged_not_fatal(
        transport: InProcessTransport, records: FleetRecords,
        caplog: pytest.LogCaptureFixture) -> None:
    fm = manager(transport, records)
    topic = m.topic("r9", m.Connection)
    transport.publish_raw(topic, b"{not json")
    transport.publish_raw(topic, b'{"headerId": 1, "connectionState": "MAYBE"}')
    with caplog.at_level(logging.WARNING):
        fm.tick(0.5)
    assert fm.robots() == []
    assert sum("connection message not used" in r.getMessage() for r in caplog.records) == 2


def test_a_lease_expiry_is_answered_on_the_asking_robots_clock(
        transport: InProcessTransport, records: FleetRecords) -> None:
    fm = manager(transport, records)
    (robot,) = online(transport, fm, ("r1", 0.0))
    responses = transport.subscribe(m.topic("r1", m.ZoneResponse))
    robot.responses.drain()
    # The robot's site time is 500 s ahead of the manager's (started earlier).
    transport.publish(m.topic("r1", m.ZoneRequest), m.ZoneRequest(
        1, "r1", "q1", "lift:A", m.ZoneRequestType.ACCESS, 10.0, sent_at=501.0))
    fm.tick(1.0)
    (answer,) = responses.drain()
    assert isinstance(answer, m.ZoneResponse)
    assert (answer.grant_type, answer.lease_expiry) == (m.GrantType.GRANTED, 511.0)
    # The records keep the manager's own time.
    (lease,) = records.live_leases(1.0)
    assert lease.expires_at == 11.0


def test_a_queued_mission_whose_point_left_the_site_is_cancelled_not_retried(
        transport: InProcessTransport, records: FleetRecords) -> None:
    fm = manager(transport, records)
    fm.submit([{"point": "door", "map": "floor1"}], mission_id="gone")
    fm.submit([{"point": "desk", "map": "floor1"}], mission_id="kept")
    before = dict(POINTS)
    del POINTS[("floor1", "door")]
    try:
        (robot,) = online(transport, fm, ("r1", 0.0))
        fm.tick(1.0)
    finally:
        POINTS.update(before)
    assert fm.mission("gone").state is MissionState.CANCELLED
    assert robot.order_ids() == ["kept-1"]


def test_a_full_queue_goes_out_max_dispatch_missions_a_tick(
        transport: InProcessTransport, records: FleetRecords) -> None:
    fm = FleetManager(transport, records, Site(), levels={"floor1": 1, "floor2": 2},
                      config=FleetManagerConfig(dispatch_period=0.5, max_dispatch=2))
    robots = online(transport, fm, ("r1", 0.0), ("r2", 5.0), ("r3", 9.0))
    for k in (1, 2, 3):
        fm.submit([{"point": "desk", "map": "floor1"}], mission_id=f"m{k}")
    fm.tick(1.0)
    assert [m.mission_id for m in fm.missions(MissionState.ACTIVE)] == ["m1", "m2"]
    fm.tick(1.1)  # the rest at the next tick, not a dispatch period later
    assert len(fm.missions(MissionState.ACTIVE)) == 3
    assert sorted(o for r in robots for o in r.order_ids()) == ["m1-1", "m2-1", "m3-1"]
