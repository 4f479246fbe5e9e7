"""Missions through the building's own fleet manager (``polynav run --robots N`` with no
broker): the same FleetManager as ``polynav fleet``, over the in-process transport, its
records in SQLite in memory."""

from __future__ import annotations

from polynav.fleet.records import MissionState
from polynav.house.building import Building
from polynav.runtime.config import RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds.world import World


def test_missions_go_to_the_nearest_free_robots_and_are_done(
        world: World, store: SiteStore) -> None:
    starts = [store.point("floor1", "initial"), store.point("floor1", "corridor_east")]
    building = Building(store, world, robots=2, starts=starts,
                        config=RuntimeConfig(people=False))
    try:
        west = building.submit([("front_desk", "floor1")], mission_id="west")
        east = building.submit([("office_4", "floor1"), ("print_room", "floor1")],
                               mission_id="east")

        def ended() -> bool:
            return all(building.mission(i).state in (MissionState.DONE, MissionState.FAILED)
                       for i in (west, east))

        assert building.advance_until(ended, timeout=200.0)
        done = {i: building.mission(i) for i in (west, east)}
        assert {i: (mi.state, mi.robot, mi.attempts) for i, mi in done.items()} == {
            "west": (MissionState.DONE, "robot1", 1), "east": (MissionState.DONE, "robot2", 1)}
        pose = building.runtimes[1].status().pose
        assert pose is not None and pose.distance_to(
            store.point("floor1", "print_room").pose) < 0.5
        assert building.fleet is not None
        whats = [e.what for e in building.fleet.audit()]
        assert whats.count("mission.done") == 2 and whats.count("order.confirmed") == 2
    finally:
        building.close()
