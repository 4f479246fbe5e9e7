"""Two fleet-manager processes, each with its own FleetRecords, on one PostgreSQL (and on one
SQLite file): a lift lease is never granted twice, and a mission is never claimed twice."""

from __future__ import annotations

import collections
import multiprocessing
import queue
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from polynav.fleet.records import FleetRecords
from tests.protocols.fleet_db import racers

PROCESSES = 2
ROUNDS = 40


@pytest.fixture(params=["sqlite", "postgresql"])
def shared_url(request: pytest.FixtureRequest, tmp_path: Path) -> str:
    if request.param == "sqlite":
        return f"sqlite:///{tmp_path / 'fleet.db'}"
    url: str = request.getfixturevalue("postgres_url")
    return url


def _run_racers(target: Callable[..., None], url: str, arg: int,
                expected: int) -> list[tuple[Any, ...]]:
    """Run ``target(url, index, arg, barrier, results)`` in PROCESSES spawned processes and
    collect ``expected`` results."""
    ctx = multiprocessing.get_context("spawn")
    barrier = ctx.Barrier(PROCESSES)
    results = ctx.Queue()
    procs = [ctx.Process(target=target, args=(url, i, arg, barrier, results))
             for i in range(PROCESSES)]
    for proc in procs:
        proc.start()
    got = []
    try:
        while len(got) < expected:
            try:
                got.append(results.get(timeout=60.0))
            except queue.Empty:
                pytest.fail(f"racers stalled after {len(got)} of {expected} results; exit "
                            f"codes {[p.exitcode for p in procs]}")
    finally:
        for proc in procs:
            proc.join(timeout=30.0)
            if proc.is_alive():
                proc.kill()
    assert [proc.exitcode for proc in procs] == [0] * PROCESSES
    return got


def test_two_fleet_managers_racing_for_one_lift_lease_exactly_one_wins(
        shared_url: str) -> None:
    FleetRecords.open(shared_url).close()  # the tables, before the racers start
    got = _run_racers(racers.race_for_lift, shared_url, ROUNDS, ROUNDS * PROCESSES)
    winners: dict[int, list[int]] = {k: [] for k in range(ROUNDS)}
    for k, index, lease_id in got:
        if lease_id is not None:
            winners[k].append(index)
    assert {k: len(w) for k, w in winners.items()} == {k: 1 for k in range(ROUNDS)}
    # Both managers won rounds: the race was real, not one process always first.
    split = collections.Counter(w[0] for w in winners.values())
    assert set(split) == set(range(PROCESSES))

    # From the audit trail: each lease lives from its grant to its release or expiry, and no
    # two leases on the lift live at once.
    with FleetRecords.open(shared_url) as records:
        entries = records.audit()
    lives: dict[int, list[float]] = {}
    for entry in entries:
        detail = entry.detail
        if detail.get("resource") != racers.LIFT:
            continue
        if entry.what == "lease.granted":
            lives[detail["lease_id"]] = [detail["granted_at"], detail["expires_at"]]
        elif entry.what == "lease.released":
            lives[detail["lease_id"]][1] = entry.at
    assert len(lives) == ROUNDS
    spans = sorted(lives.values())
    assert all(earlier[1] <= later[0] for earlier, later in zip(spans[:-1], spans[1:], strict=True))
    assert {e.actor for e in entries if e.what == "lease.granted"} == {"fm-0", "fm-1"}


def test_two_fleet_managers_claiming_at_once_never_share_a_mission(shared_url: str) -> None:
    missions = 12
    robots = 8  # per process: 16 claims for 12 missions
    with FleetRecords.open(shared_url) as records:
        for k in range(missions):
            records.add_mission([{"point": f"p{k}"}], now=float(k), mission_id=f"m{k}")
    got = _run_racers(racers.race_for_missions, shared_url, robots, robots * PROCESSES)
    claimed = [mission for _, mission in got if mission is not None]
    assert sorted(claimed) == sorted(f"m{k}" for k in range(missions))
    with FleetRecords.open(shared_url) as records:
        by_mission = {m.mission_id: m.robot for m in records.missions()}
        assert sum(e.what == "mission.claimed" for e in records.audit()) == missions
    assert by_mission == {mission: robot for robot, mission in got if mission is not None}
