"""What each fleet-manager process does in the race tests: its own FleetRecords on the shared
database, started with multiprocessing's spawn (a fresh interpreter, as a second fleet manager
would be), in step with the others through a barrier."""

from __future__ import annotations

from typing import Any

from polynav.fleet.records import FleetRecords

LIFT = "lift:A"
ROUND = 10.0  # site seconds between rounds
HOLD = 5.0  # lease duration: lapsed before the next round


def race_for_lift(url: str, index: int, rounds: int, barrier: Any, results: Any) -> None:
    """Each round, at the same instant as the others, ask for the lift for this process's
    robot; once all have asked, the winner of an odd round releases it (an even round's lease
    lapses). Releasing before the others asked would let them in at the round's own time,
    before the release's: site time running backwards, which one fleet's clock never does."""
    with FleetRecords.open(url, name=f"fm-{index}") as records:
        for k in range(rounds):
            barrier.wait(timeout=30.0)
            now = k * ROUND
            lease = records.grant_lease(LIFT, f"robot-{index}", now=now, duration=HOLD)
            barrier.wait(timeout=30.0)
            if lease is not None and k % 2 == 1:
                records.release(LIFT, lease.holder, now=now + 1.0)
            results.put((k, index, None if lease is None else lease.lease_id))


def race_for_missions(url: str, index: int, robots: int, barrier: Any, results: Any) -> None:
    """Claim missions for this process's robots, all at once with the other process."""
    with FleetRecords.open(url, name=f"fm-{index}") as records:
        barrier.wait(timeout=30.0)
        for j in range(robots):
            mission = records.claim_mission(f"robot-{index}-{j}", now=1.0)
            results.put((f"robot-{index}-{j}", None if mission is None else mission.mission_id))
