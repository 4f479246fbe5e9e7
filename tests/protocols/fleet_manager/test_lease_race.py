"""Two fleet managers on one real PostgreSQL, each with its own lease book and its own robot,
asked for one lift car at the same moment: exactly one robot is granted it, every time."""

from __future__ import annotations

import threading
from collections.abc import Iterator

import pytest

from polynav.fleet import messages as m
from polynav.fleet.manager import FleetManager
from polynav.fleet.records import FleetRecords, RecordsConfig
from polynav.fleet.transport import InProcessTransport
from tests.helpers.scripted_vehicle import Robot, Site

RACES = 40


@pytest.fixture
def managers(postgres_url: str) -> Iterator[tuple[FleetManager, FleetManager]]:
    config = RecordsConfig(connect_wait=5.0, retry_for=5.0)
    with FleetRecords.open(postgres_url, name="fm1", config=config) as one, \
            FleetRecords.open(postgres_url, name="fm2", config=config) as two:
        assert one.is_postgres
        yield (FleetManager(InProcessTransport(), one, Site()),
               FleetManager(InProcessTransport(), two, Site()))


def _robot(fm: FleetManager, serial: str) -> Robot:
    transport = fm.master.transport
    assert isinstance(transport, InProcessTransport)
    robot = Robot(transport, serial)
    robot.connection(m.ConnectionState.ONLINE)
    return robot


def test_two_managers_racing_for_one_lift_grant_it_to_exactly_one_robot_every_time(
        managers: tuple[FleetManager, FleetManager]) -> None:
    fm1, fm2 = managers
    a, b = _robot(fm1, "a"), _robot(fm2, "b")
    fm1.tick(0.0)
    fm2.tick(0.0)
    winners = []
    for race in range(RACES):
        now = 1.0 + race
        a.ask("lift:A")
        b.ask("lift:A")
        gate = threading.Barrier(2)

        def tick(fm: FleetManager, at: float = now,
                 gate: threading.Barrier = gate) -> None:
            gate.wait()
            fm.tick(at)

        threads = [threading.Thread(target=tick, args=(fm,)) for fm in (fm1, fm2)]
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join(timeout=20.0)
        got = {"a": a.grants(), "b": b.grants()}
        granted = [s for s, answers in got.items() if m.GrantType.GRANTED in answers]
        assert len(granted) == 1, (race, got)
        winner = granted[0]
        loser = "b" if winner == "a" else "a"
        assert got[loser] == [m.GrantType.QUEUED], (race, got)
        live = fm1.records.live_leases(now)
        assert [(lease.resource, lease.holder) for lease in live] == [("lift:A", winner)]
        winners.append(winner)
        # The winner gets off; the loser's manager grants it at its next tick (the records
        # agree now), and it releases too, leaving the car free for the next race.
        winner_fm, loser_fm = (fm1, fm2) if winner == "a" else (fm2, fm1)
        winner_robot, loser_robot = (a, b) if winner == "a" else (b, a)
        winner_robot.release("lift:A")
        winner_fm.tick(now + 0.2)
        loser_fm.tick(now + 0.3)
        assert loser_robot.grants() == [m.GrantType.GRANTED], race
        loser_robot.release("lift:A")
        loser_fm.tick(now + 0.4)
        winner_fm.tick(now + 0.4)
        assert fm1.records.live_leases(now + 0.4) == ()
