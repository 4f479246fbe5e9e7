"""The multi-map router on the demo site: car choice, each "no route" reason, and the path cost
cache that a keepout change invalidates."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from polynav.maps.costmap import CostmapConfig
from polynav.maps.keepout import VirtualWall
from polynav.planning.grid_planner import GridPlannerConfig
from polynav.robot.lift import LiftMode, LiftRequest
from polynav.robot.sim.config import SimConfig
from polynav.robot.sim.scene import Scene
from polynav.routing import connections
from polynav.routing.errors import NoRoute, NoRouteReason
from polynav.routing.path_costs import PlannedPathCosts
from polynav.routing.route import DriveLeg, LiftLeg
from polynav.routing.router import Router
from polynav.store import SiteStore
from polynav.store.records import ConnectionRecord
from polynav.worlds.world import World


@pytest.fixture
def store(tmp_path: Path, world: World) -> Iterator[SiteStore]:
    s = SiteStore.open(tmp_path / "data", seed_world=world)
    yield s
    s.close()


@pytest.fixture
def scene(world: World) -> Scene:
    return Scene(world, SimConfig(), people=False)


def _route(store: SiteStore, scene: Scene, start: tuple[str, str], goal: tuple[str, str],
           **kwargs: object) -> tuple[PlannedPathCosts, object]:
    costs = PlannedPathCosts(store, CostmapConfig(), GridPlannerConfig())
    router = Router(store, costs)
    a = store.point(*start)
    b = store.point(*goal)
    route = router.route(connections.parse(store.connections()), scene.lifts,
                         start_map=a.map_name, start=a.pose, goal_map=b.map_name, goal=b.pose,
                         goal_point=b.name, **kwargs)  # type: ignore[arg-type]
    return costs, route


def test_floor1_to_floor3_rides_lift_1_in_three_legs(store: SiteStore, scene: Scene) -> None:
    _, route = _route(store, scene, ("floor1", "office_1"), ("floor3", "room_301"))
    legs = route.legs  # type: ignore[attr-defined]
    assert [leg.kind for leg in legs] == ["drive", "lift", "drive"]
    lift = legs[1]
    assert isinstance(lift, LiftLeg)
    assert (lift.car, lift.from_floor, lift.to_floor) == ("lift_1", "floor1", "floor3")
    assert lift.waiting_from is not None and lift.waiting_from.x == 38.9
    assert isinstance(legs[0], DriveLeg) and legs[0].point == "lift_1_outside"
    assert legs[2] == DriveLeg("floor3", store.point("floor3", "room_301").pose, "room_301")
    assert route.cost > 60.0  # type: ignore[attr-defined]


def test_a_busy_car_makes_the_other_car_the_quicker(store: SiteStore, scene: Scene) -> None:
    _, first = _route(store, scene, ("floor1", "lobby"), ("floor2", "lounge"))
    car = first.cars[0]  # type: ignore[attr-defined]
    scene.lifts[car].request(LiftRequest("someone_else", "floor1"))
    _, second = _route(store, scene, ("floor1", "lobby"), ("floor2", "lounge"))
    assert second.cars == ({"lift_1": "lift_2", "lift_2": "lift_1"}[car],)  # type: ignore


def test_out_of_service_car_falls_back_or_fails_with_the_reason(
    store: SiteStore, scene: Scene
) -> None:
    scene.lifts["lift_1"].set_mode(LiftMode.OUT_OF_SERVICE)
    _, route = _route(store, scene, ("floor1", "lobby"), ("floor2", "lounge"))
    assert route.cars == ("lift_2",)  # type: ignore[attr-defined]
    with pytest.raises(NoRoute, match="out of service: lift_1") as info:
        _route(store, scene, ("floor1", "lobby"), ("floor3", "room_301"))
    assert info.value.reason is NoRouteReason.OUT_OF_SERVICE
    with pytest.raises(NoRoute, match="already failed: lift_2"):
        _route(store, scene, ("floor1", "lobby"), ("floor2", "lounge"), exclude={"lift_2"})


def test_map_no_lift_serves_fails_with_no_lift(store: SiteStore, scene: Scene) -> None:
    records = [r for r in store.connections() if r.name != "lift_1"]
    store.set_connections(records)
    with pytest.raises(NoRoute, match="map 'floor3'") as info:
        _route(store, scene, ("floor1", "lobby"), ("floor3", "room_301"))
    assert info.value.reason is NoRouteReason.NO_LIFT


def test_walled_off_goal_is_unreachable_and_the_cache_follows_keepouts(
    store: SiteStore, scene: Scene
) -> None:
    costs, _ = _route(store, scene, ("floor1", "lobby"), ("floor3", "room_301"))
    plans = costs.plans
    # room_301's door (x 9.5..10.7 on the corridor's north wall, y 13.0) walled off.
    store.set_keepouts("floor3", [VirtualWall(((9.3, 13.05), (10.9, 13.05)), thickness=0.2)])
    with pytest.raises(NoRoute) as info:
        _route(store, scene, ("floor1", "lobby"), ("floor3", "room_301"))
    assert info.value.reason is NoRouteReason.UNREACHABLE
    store.set_keepouts("floor3", [])
    costs2, route = _route(store, scene, ("floor1", "lobby"), ("floor3", "room_301"))
    assert route.cars == ("lift_1",) and plans > 0  # type: ignore[attr-defined]
    # One router, the same question twice: the second is answered from the cache.
    router = Router(store, costs2)
    a, b = store.point("floor1", "lobby"), store.point("floor3", "room_301")
    before = costs2.plans
    router.route(connections.parse(store.connections()), scene.lifts, start_map="floor1",
                 start=a.pose, goal_map="floor3", goal=b.pose)
    assert costs2.plans == before


def test_same_map_is_one_drive_and_a_direct_connection_is_a_switch(
    store: SiteStore, scene: Scene
) -> None:
    _, route = _route(store, scene, ("floor1", "lobby"), ("floor1", "kitchen"))
    assert [leg.kind for leg in route.legs] == ["drive"]  # type: ignore[attr-defined]
    store.set_connections([ConnectionRecord("c1", {
        "type": "direct", "from": {"map": "floor1", "point": "corridor_west"},
        "to": {"map": "floor2", "point": "corridor_west"}})])
    _, route = _route(store, scene, ("floor1", "lobby"), ("floor2", "lounge"))
    assert [leg.kind for leg in route.legs] == ["drive", "switch", "drive"]  # type: ignore


def test_malformed_connections_are_skipped() -> None:
    parsed = connections.parse([
        ConnectionRecord("bad", {"type": "lift", "stops": [{"floor": "f1"}]}),
        ConnectionRecord("odd", ["not", "an", "object"]),
        ConnectionRecord("ok", {"type": "direct", "from": {"map": "a", "point": "p"},
                                "to": {"map": "b", "point": "q"}}),
    ])
    assert parsed.lifts == () and [d.name for d in parsed.directs] == ["ok"]
