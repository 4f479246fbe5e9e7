"""The built-in demo site keeps its promises: clearance, reachability, two lift cars, points."""

from __future__ import annotations

import importlib.util
import math
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy import ndimage

from polynav.site import PointKind
from polynav.worlds import BUILTIN_DIR
from polynav.worlds.world import World, WorldFloor

REPO = Path(__file__).resolve().parents[3]
ROBOT_RADIUS = 0.25
POINT_CLEARANCE = 0.45


def _clearance(floor: WorldFloor) -> np.ndarray:
    """Distance [m] from each cell centre to the nearest occupied cell's edge."""
    res = floor.map.info.resolution
    return ndimage.distance_transform_edt(~floor.map.occupied()) * res - res / 2


def test_demo_has_three_floors_starting_at_the_initial_point_of_floor_one(world: World) -> None:
    assert [f.name for f in world.floors] == ["floor1", "floor2", "floor3"]
    assert [f.level for f in world.floors] == [1, 2, 3]
    start = world.floor(world.start_floor)
    initial = [p for p in start.points if p.kind is PointKind.INITIAL]
    assert len(initial) == 1
    assert initial[0].pose == world.start_pose
    assert start.map.info.resolution == 0.05
    assert start.map.info.size_m == pytest.approx((41.0, 25.0))


@pytest.mark.parametrize(("floor_name", "cars"), [("floor1", 2), ("floor2", 2), ("floor3", 1)])
def test_floor_has_named_points_an_initial_point_and_both_points_of_each_car(
    world: World, floor_name: str, cars: int
) -> None:
    floor = world.floor(floor_name)
    kinds = [p.kind for p in floor.points]
    assert kinds.count(PointKind.GENERAL) >= 10
    assert kinds.count(PointKind.INITIAL) == 1
    assert kinds.count(PointKind.LIFT_OUTSIDE) == cars
    assert kinds.count(PointKind.LIFT_INSIDE) == cars
    assert all(p.map_name == floor.map_name for p in floor.points)
    assert len({p.name for p in floor.points}) == len(floor.points)


def test_floor_one_has_a_charger_facing_its_wall(world: World) -> None:
    floor = world.floor("floor1")
    chargers = [p for p in floor.points if p.kind is PointKind.CHARGER]
    assert [c.name for c in chargers] == ["charger"]
    pose = chargers[0].pose
    # Straight ahead (the docking direction) the wall is near; behind, the room is open.
    occupied = floor.map.occupied()
    ahead = [floor.map.info.world_to_cell(pose.x + d * math.cos(pose.theta),
                                          pose.y + d * math.sin(pose.theta)) for d in (0.7,)]
    assert all(occupied[iy, ix] for ix, iy in ahead)
    ix, iy = floor.map.info.world_to_cell(pose.x - 2.0 * math.cos(pose.theta),
                                          pose.y - 2.0 * math.sin(pose.theta))
    assert not occupied[iy, ix]


@pytest.mark.parametrize("floor_name", ["floor1", "floor2", "floor3"])
def test_every_point_is_free_with_clearance_for_the_robot(world: World, floor_name: str) -> None:
    floor = world.floor(floor_name)
    clearance = _clearance(floor)
    for p in floor.points:
        ix, iy = floor.map.info.world_to_cell(p.pose.x, p.pose.y)
        assert floor.map.data[iy, ix] == 0, p.name
        assert clearance[iy, ix] >= POINT_CLEARANCE, (p.name, clearance[iy, ix])


@pytest.mark.parametrize("floor_name", ["floor1", "floor2", "floor3"])
@pytest.mark.parametrize("radius", [ROBOT_RADIUS, POINT_CLEARANCE - 0.01])
def test_every_point_is_reachable_from_the_initial_point(
    world: World, floor_name: str, radius: float
) -> None:
    # Free space eroded by the disk: its connected parts are where the disk's centre can roam.
    # A disk of 0.44 m passing means every gap on the way is at least 0.88 m wide.
    floor = world.floor(floor_name)
    passable = (floor.map.data == 0) & (_clearance(floor) >= radius)
    labels, _ = ndimage.label(passable)
    initial = next(p for p in floor.points if p.kind is PointKind.INITIAL)
    ix, iy = floor.map.info.world_to_cell(initial.pose.x, initial.pose.y)
    home = labels[iy, ix]
    assert home != 0
    for p in floor.points:
        ix, iy = floor.map.info.world_to_cell(p.pose.x, p.pose.y)
        assert labels[iy, ix] == home, p.name


def test_lift_shaft_is_at_the_same_place_on_both_floors(world: World) -> None:
    one, two = world.floor("floor1"), world.floor("floor2")
    assert one.lift is not None and one.lift == two.lift
    assert one.map.info == two.map.info
    x0, y0, x1, y1 = one.lift.bounds
    assert (x1 - x0, y1 - y0) == pytest.approx((2.0, 2.0))
    for floor in (one, two):
        inside = floor.point("lift_1_inside").pose
        assert one.lift.contains(inside.x, inside.y)
        outside = floor.point("lift_1_outside").pose
        assert not one.lift.contains(outside.x, outside.y)
        # The inside point faces out through the door; the outside point faces the door.
        assert inside.theta == pytest.approx(one.lift.door_heading)
        assert outside.theta == pytest.approx(-one.lift.door_heading)
    # The car's free cells are the same on both floors, and the open door joins it to the lobby.
    c0, r0 = one.map.info.world_to_cell(x0 - 0.3, y0 - 0.3)
    c1, r1 = one.map.info.world_to_cell(x1 + 0.3, y1 + 0.3)
    assert np.array_equal(one.map.data[r0:r1, c0:c1], two.map.data[r0:r1, c0:c1])


def test_two_cars_car_a_serves_every_floor_car_b_the_lower_two(world: World) -> None:
    a, b = world.lift("lift_1"), world.lift("lift_2")
    assert a.floors == ("floor1", "floor2", "floor3")
    assert b.floors == ("floor1", "floor2")
    assert world.floor("floor1").lift == a.shaft
    for car in (a, b):
        for name in car.floors:
            floor = world.floor(name)
            inside = floor.point(car.inside).pose
            assert car.shaft.contains(inside.x, inside.y)
            assert not car.shaft.contains(*(lambda p: (p.x, p.y))(floor.point(car.outside).pose))
            ix, iy = floor.map.info.world_to_cell(inside.x, inside.y)
            assert floor.map.data[iy, ix] == 0
    # Car B's shaft is solid core on floor 3: nothing reaches it there.
    three = world.floor("floor3")
    ix, iy = three.map.info.world_to_cell(b.shaft.x, b.shaft.y)
    assert three.map.occupied()[iy, ix]
    assert a.shaft.bounds[0] - b.shaft.bounds[2] > 0.1  # a wall between the cars


@pytest.mark.parametrize("floor_name", ["floor1", "floor2"])
def test_walkers_cross_the_main_corridor_and_keep_clear_of_walls(
    world: World, floor_name: str
) -> None:
    floor = world.floor(floor_name)
    assert 2 <= len(floor.people) <= 3
    clearance = _clearance(floor)
    corridor_crossings = 0
    for person in floor.people:
        wps = np.asarray(person.waypoints)
        if person.loop:
            wps = np.vstack([wps, wps[:1]])
        corridor_crossings += bool(wps[:, 1].min() < 11.0 and wps[:, 1].max() > 13.0)
        for a, b in zip(wps[:-1], wps[1:], strict=True):
            for t in np.linspace(0.0, 1.0, 200):
                x, y = a + t * (b - a)
                ix, iy = floor.map.info.world_to_cell(x, y)
                assert clearance[iy, ix] >= person.radius, (person, x, y)
    assert corridor_crossings >= 1


def test_committed_demo_files_are_what_the_generator_writes(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    script = REPO / "tools" / "make_demo_world.py"
    spec = importlib.util.spec_from_file_location("make_demo_world", script)
    assert spec is not None and spec.loader is not None
    generator = importlib.util.module_from_spec(spec)
    monkeypatch.setitem(sys.modules, "make_demo_world", generator)  # dataclasses look it up
    spec.loader.exec_module(generator)
    floors = [generator.floor_one(), generator.floor_two(), generator.floor_three()]
    assert [generator.check(f) for f in floors] == [[], [], []]
    assert generator.check_waiting(floors) == []
    generator.write(floors, tmp_path)
    committed = BUILTIN_DIR / "demo"
    names = sorted(p.name for p in committed.iterdir())
    assert names == ["floor1.png", "floor1.yaml", "floor2.png", "floor2.yaml", "floor3.png",
                     "floor3.yaml", "world.yaml"]
    for name in names:
        assert (tmp_path / name).read_bytes() == (committed / name).read_bytes(), name
