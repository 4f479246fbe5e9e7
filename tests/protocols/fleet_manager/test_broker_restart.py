"""A broker restart costs no mission (issue #36): the fleet manager and two robots on a real
Mosquitto, missions queued and running when the broker is killed; one more is posted while it
is away. Every mission ends done exactly once: one dispatch each, no order run twice, none
lost. (The broker going down delivers the robots' last wills: the manager requeues their
missions, and each robot, back and still driving its order, resumes its own.)

The building runs on simulated time; waits across the restart (the MQTT clients' reconnection
with backoff) are wall time, the simulation paced 2 ms of wall time per control period
meanwhile so the network threads get their turn.
"""

from __future__ import annotations

import time
from collections import Counter
from collections.abc import Iterator

import pytest

from polynav.fleet.records import MissionState
from polynav.fleet.vehicle import VehicleConfig
from polynav.house.building import Building
from polynav.runtime.config import RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds.world import World
from tests.helpers.mosquitto import Mosquitto

WAIT = 20.0  # [s of wall time] for a reconnection


@pytest.fixture
def building(broker: Mosquitto, world: World, store: SiteStore) -> Iterator[Building]:
    """Two robots on floor 1 and the fleet manager, all on ``broker``."""
    starts = [store.point("floor1", "initial"), store.point("floor1", "corridor_west")]
    built = Building(store, world, robots=2, starts=starts,
                     config=RuntimeConfig(people=False),
                     vehicles=VehicleConfig(broker.url, visualization_period=None))
    try:
        yield built
    finally:
        built.close()


def _paced(building: Building, seconds: float) -> None:
    """Run the building ``seconds`` of wall time, 2 ms of wall time per control period."""
    deadline = time.monotonic() + seconds

    def over() -> bool:
        time.sleep(0.002)
        return time.monotonic() >= deadline

    building.advance_until(over, timeout=3600.0)


def test_missions_queued_and_running_through_a_broker_restart_each_end_once(
        broker: Mosquitto, building: Building) -> None:
    fleet = building.fleet
    assert fleet is not None
    first = [building.submit([(point, "floor1")], mission_id=f"m{k}")
             for k, point in enumerate(("office_3", "office_1", "lobby", "office_2"), 1)]

    def two_driving() -> bool:
        active = fleet.missions(MissionState.ACTIVE)
        return len(active) == 2 and all(
            (s := fleet.master.state(m.robot or "")) is not None and s.driving for m in active)

    assert building.advance_until(two_driving, timeout=60.0)
    assert len(fleet.missions(MissionState.QUEUED)) == 2

    broker.stop()
    assert all(t.wait_disconnected(WAIT) for t in building.mqtt_clients)
    # The robots drive on; a mission posted now is queued, and any dispatched now goes out
    # to no one (QoS 0): the manager must send it again once a state does not confirm it.
    late = building.submit([("front_desk", "floor1")], mission_id="late")
    _paced(building, 2.0)
    broker.restart()  # same port; it has forgotten every retained message
    _paced(building, 1.0)
    assert all(t.wait_connected(WAIT) for t in building.mqtt_clients)

    missions = [*first, late]

    def all_ended() -> bool:
        return all(fleet.mission(m).state in (MissionState.DONE, MissionState.FAILED,
                                              MissionState.CANCELLED) for m in missions)

    assert building.advance_until(all_ended, timeout=600.0)
    ended = {m: fleet.mission(m) for m in missions}
    assert {m: e.state for m, e in ended.items()} == dict.fromkeys(missions, MissionState.DONE)
    # Each claimed once: nothing went back to the queue, so no second order for any mission.
    assert {m: e.attempts for m, e in ended.items()} == dict.fromkeys(missions, 1)
    events = fleet.events_after(0)
    for kind in ("mission.dispatched", "mission.done"):
        assert Counter(e.detail["mission"] for e in events if e.kind == kind) == Counter(
            missions), kind
    assert not [e for e in events if e.kind == "mission.failed"]
    # Mosquitto going down delivers the robots' last wills: their missions went back to the
    # queue, and each robot, back and still driving, resumed its own.
    requeued = [(e.detail["mission"], e.detail["robot"]) for e in events
                if e.kind == "mission.requeued"]
    resumed = [(e.detail["mission"], e.detail["robot"]) for e in events
               if e.kind == "mission.resumed"]
    assert sorted(requeued) == sorted(resumed)
    # The robots ran each mission's order once between them, and succeeded.
    orders = {f"{m}-1": ended[m].robot for m in missions}
    for serial in building.serials:
        agent = building.agent(serial)
        ran = {o for o in orders if agent.outcome_of(o) is not None}
        assert ran == {o for o, robot in orders.items() if robot == serial}
        assert all(agent.outcome_of(o) == "succeeded" for o in ran)
    assert all(t.stats().connects == 2 for t in building.mqtt_clients)
