"""Several robots in one building, whole missions on simulated time (issue 11 item 6).

Robots share one simulated world and one clock; the fleet grants narrow passages as leases
(docs/fleet.md). Judged on ground truth: every order succeeds, no robot touches another, and no
one waits for ever.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

from polynav.errors import NotFound
from polynav.fleet.master_control import Stop
from polynav.geometry import Pose2D
from polynav.house.building import Building
from polynav.runtime.config import RuntimeConfig
from polynav.runtime.events import NavigationWaiting
from polynav.site import Point, PointKind
from polynav.store.site_store import SiteStore
from polynav.worlds.from_map import FromMapOptions, load_plan, plan_world, to_world
from polynav.worlds.world import World
from tests.conftest import DATA


def _all_done(building: Building) -> bool:
    return all(agent.outcome is not None for agent in building.agents)


def _collisions(building: Building) -> list[object]:
    return [c for runtime in building.runtimes for c in runtime.simulation.collisions]


def test_two_robots_meeting_at_one_door_both_arrive_one_waits_no_collision(
        world: World, store: SiteStore) -> None:
    # Office 1's door (x 11.0..12.2 in the wall at y = 13) is one robot wide, and the 2 m
    # corridor outside too narrow for two robots to pass: one zone. Robot 1 stands inside the
    # office and leaves for the lobby; robot 2, in the corridor, goes in at the same moment.
    inside = Point("start_in_office_1", "floor1", Pose2D(11.6, 15.5, -math.pi / 2),
                   PointKind.GENERAL)
    corridor = Point("start_in_corridor", "floor1", Pose2D(14.8, 12.0, math.pi),
                     PointKind.GENERAL)
    store.add_point(Point("desk_office_1", "floor1", Pose2D(11.6, 16.5, math.pi / 2)))
    building = Building(store, world, robots=2, starts=[inside, corridor],
                        config=RuntimeConfig(people=False))
    door = building.zones["floor1"].zone_at(11.6, 13.0)
    assert door != 0
    building.send("robot1", "lobby", "floor1")
    building.send("robot2", "desk_office_1", "floor1")
    granted: list[str] = []

    def watch() -> bool:
        for agent in building.agents:
            if building.zones["floor1"].zone_id(door) in agent.traffic.held and (
                    not granted or granted[-1] != agent.serial_number):
                granted.append(agent.serial_number)
        return _all_done(building)

    assert building.advance_until(watch, timeout=240.0), "deadlock: an order never ended"
    assert [a.outcome for a in building.agents] == ["succeeded", "succeeded"]
    assert _collisions(building) == []
    # One robot had the zone first and went on; the other stood still until it was free.
    assert sorted(granted) == ["robot1", "robot2"]
    first, second = granted
    waiter = building.agent(second).traffic
    assert waiter.waits >= 1 and waiter.wait_time > 0.0
    assert building.agent(first).traffic.waits == 0
    for runtime, point in zip(building.runtimes, ("lobby", "desk_office_1"), strict=True):
        goal = store.point("floor1", point).pose
        assert runtime.simulation.true_pose.distance_to(goal) < 0.1
    # Every lease went back: nothing is held once the orders are done.
    assert all(building.master.leases.leases(z) == () for z in building.master.leases.resources())


Draw = Callable[[str, dict[str, str]], str]
"""The next goal for robot ``serial``, given where each robot is bound (or stands, at first)."""


def _dispatch(building: Building, map_name: str, missions: int, draw: Draw,
              bound: dict[str, str] | None = None) -> list[str]:
    """Send each idle robot to the point ``draw`` picks until ``missions`` orders have ended;
    each order's outcome, ``"<serial> <point>: <outcome>"``."""
    bound = dict(bound or {})
    pending: dict[str, str] = {}
    results: list[str] = []
    sent = 0
    while len(results) < missions:
        for serial in building.serials:
            if serial in pending or sent == missions:
                continue
            bound[serial] = draw(serial, bound)
            pending[serial] = building.send(serial, bound[serial], map_name)
            sent += 1
        assert building.advance_until(
            lambda: any(building.outcome(s, o) is not None for s, o in pending.items()),
            timeout=600.0,
        ), "deadlock: no order ended in 10 simulated minutes"
        for serial, order_id in list(pending.items()):
            result = building.outcome(serial, order_id)
            if result is not None:
                results.append(f"{serial} {bound[serial]}: {result}")
                del pending[serial]
    return results


@pytest.mark.slow
def test_twenty_random_missions_for_three_robots_all_succeed(
        world: World, store: SiteStore) -> None:
    starts = ("initial", "lobby", "office_3")
    building = Building(store, world, robots=3, config=RuntimeConfig(people=False, seed=3),
                        starts=[store.point("floor1", name) for name in starts])
    goals = [p.name for p in store.points(map_name="floor1") if p.kind is PointKind.GENERAL]
    rng = np.random.default_rng(11)

    def draw(serial: str, bound: dict[str, str]) -> str:
        # No robot is sent where another is or goes.
        taken = {goal for other, goal in bound.items() if other != serial}
        return str(rng.choice([g for g in goals if g not in taken]))

    results = _dispatch(building, "floor1", 20, draw,
                        bound=dict(zip(building.serials, starts, strict=True)))
    assert all(r.endswith(": succeeded") for r in results), results
    assert _collisions(building) == []


def test_an_order_canceled_by_instant_action_ends_failed_and_the_state_says_so(
        world: World, store: SiteStore) -> None:
    building = Building(store, world, robots=1, config=RuntimeConfig(people=False))
    order_id = building.send("robot1", "kitchen", "floor1")
    building.advance(3.0)
    state = building.master.state("robot1")
    assert state is not None and state.order_id == order_id
    assert [n.node_id for n in state.node_states] == ["kitchen"]
    assert state.navigation_state == "running"
    assert building.outcome("robot1", order_id) is None
    building.master.cancel_order("robot1")
    building.advance(1.5)
    assert building.outcome("robot1", order_id) == "failed: canceled"
    state = building.master.state("robot1")
    assert state is not None and [e.error_type for e in state.errors] == ["orderFailed"]
    (entry,) = building.entries()
    assert entry.order_state == "failed" and entry.navigation_state == "canceled"


def test_an_order_to_a_point_the_site_lacks_fails_with_the_reason(
        world: World, store: SiteStore) -> None:
    building = Building(store, world, robots=1, config=RuntimeConfig(people=False))
    with pytest.raises(NotFound):
        building.send("robot1", "nowhere", "floor1")
    order_id = building.master.send_order("robot1", [Stop("nowhere", "floor9", Pose2D(1, 1, 0))])
    building.advance(0.5)
    outcome = building.outcome("robot1", order_id)
    assert outcome is not None and outcome.startswith("failed: node nowhere")
    assert building.runtimes[0].status().navigation_state == "idle"


def test_a_robot_sent_where_another_stands_waits_for_it_to_leave_then_arrives(
        world: World, store: SiteStore) -> None:
    # Robot 1 stands on office 3's point; robot 2 is sent there. Cleared and re-planned, the
    # goal is still occupied, but not by the map: robot 2 waits near it (told once, "goal
    # occupied") instead of failing, and arrives once robot 1 has been sent away.
    building = Building(store, world, robots=2, config=RuntimeConfig(people=False),
                        starts=[store.point("floor1", "office_3"),
                                store.point("floor1", "corridor_west")])
    waits = building.agent("robot2").runtime.bus.subscribe()
    second = building.send("robot2", "office_3", "floor1")
    told: list[str] = []

    def waiting() -> bool:
        told.extend(e.cause for e in waits.get_nowait() if isinstance(e, NavigationWaiting))
        return bool(told) or building.outcome("robot2", second) is not None

    assert building.advance_until(waiting, timeout=120.0)
    assert told == ["goal occupied"], building.outcome("robot2", second)
    building.advance(20.0)  # it stands, short of robot 1, and the goal does not fail
    assert building.outcome("robot2", second) is None
    assert building.agent("robot2").runtime.status().navigation_state == "running"
    first = building.send("robot1", "office_4", "floor1")
    assert building.advance_until(
        lambda: building.outcome("robot1", first) is not None
        and building.outcome("robot2", second) is not None, timeout=240.0)
    assert (building.outcome("robot1", first), building.outcome("robot2", second)) == (
        "succeeded", "succeeded")
    goal = store.point("floor1", "office_3").pose
    assert building.agent("robot2").runtime.simulation.true_pose.distance_to(goal) < 0.1
    assert _collisions(building) == []


@pytest.mark.slow
@pytest.mark.parametrize(("plan", "cell"), [
    ("room-32-32-4", 1.0),  # 3 m rooms, 1 m doors: each door a zone, robots wait in the rooms
    ("maze-32-32-4", 0.5),  # 2 m corridors, every one narrow: the whole maze is one zone
])
def test_three_robots_on_floor_plans_never_tuned_on_all_arrive(plan: str, cell: float,
                                                               tmp_path: Path) -> None:
    # The traffic rule finds its zones in any map: the same fleet on MovingAI plans it was
    # never tuned on, with points placed at random where a robot fits.
    options = FromMapOptions(cell=cell, points=12, walkers=0, seed=1)
    grid = load_plan(DATA / "movingai" / f"{plan}.map", options)
    world = to_world(plan_world(plan, grid, options), options)
    with SiteStore.open(tmp_path / "data", seed_world=world) as store:
        points = [p for p in store.points(map_name="floor1") if p.kind is PointKind.GENERAL]
        building = Building(store, world, robots=3, starts=points[:3],
                            config=RuntimeConfig(people=False, seed=1))
        assert building.zones["floor1"].count >= 1
        rng = np.random.default_rng(5)

        def draw(serial: str, bound: dict[str, str]) -> str:
            # As a dispatcher would: never where another robot is bound for or stands within
            # 1 m of (its own point included).
            stood = {p.name for runtime in building.runtimes for p in points
                     if p.pose.distance_to(runtime.status().pose) <= 1.0}
            return str(rng.choice([p.name for p in points
                                   if p.name not in stood | set(bound.values())]))

        results = _dispatch(building, "floor1", 12, draw)
        assert all(r.endswith(": succeeded") for r in results), results
        assert _collisions(building) == []


def test_a_robot_giving_way_to_a_walker_in_a_door_is_not_frozen_by_the_traffic_rule(
        world: World, store: SiteStore) -> None:
    # Floor 2's door at (17.55, 13) into the room north of the corridor, with a walker's route
    # through it (17.55, 14.5 <-> 9.5). Robot 1 stands just inside, bound for room_205, the
    # walker coming at it; robot 2 right behind it in the corridor, bound for the same room;
    # robot 3 going east along the corridor past the door. Robot 1's first plan fails (the
    # walker), it waits for people with no path and backs out of the room's zone into the
    # corridor's, which robot 2 holds: the traffic rule paused it there for that zone, so it
    # stood in the doorway, the walker could not get out, robot 2 waited for the walker and
    # failed `blocked by person`, and robot 3 waited for the corridor for minutes. A robot with
    # no path is not paused for the zone it stands in: it gives way, the walker passes.
    starts = [Point("in_the_door", "floor2", Pose2D(17.45, 13.4, math.pi / 2),
                    PointKind.GENERAL),
              Point("behind_it", "floor2", Pose2D(17.45, 12.4, math.pi / 2), PointKind.GENERAL),
              Point("along", "floor2", Pose2D(15.9, 12.0, 0.0), PointKind.GENERAL)]
    for point in starts:
        store.add_point(point)
    store.add_point(Point("in_room_205", "floor2", Pose2D(20.0, 17.0, 0.0)))
    building = Building(store, world, robots=3, starts=starts,
                        config=RuntimeConfig(people=True, seed=1))
    building.send("robot1", "room_205", "floor2")
    building.send("robot2", "in_room_205", "floor2")
    building.send("robot3", "corridor_east", "floor2")
    assert building.advance_until(lambda: _all_done(building), 200.0)
    assert [agent.outcome for agent in building.agents] == ["succeeded"] * 3
    assert _collisions(building) == []
