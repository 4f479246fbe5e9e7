"""Doors and gates in world files: read with their defaults, bad ones refused with the field."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import pytest

from polynav.errors import InvalidRequest
from polynav.worlds import load_world
from polynav.worlds.errors import WorldFormatError
from polynav.worlds.world import DoorKind, WorldDoor
from polynav.worlds.world_file import read_world
from tests.unit.worlds.test_world_file import _document, _write


def _with_doors(*doors: dict[str, Any]) -> dict[str, Any]:
    doc = _document()
    doc["doors"] = list(doors)
    return doc


def test_doors_are_read_by_segment_or_by_centre_heading_and_width(tmp_path: Path) -> None:
    world = read_world(_write(tmp_path, _with_doors(
        {"name": "d1", "floor": "ground", "x1": 3.0, "y1": 1.0, "x2": 3.0, "y2": 3.0},
        {"name": "g1", "floor": "ground", "x": 2.0, "y": 2.0, "theta": 0.0, "width": 1.5,
         "kind": "gate", "open_time": 1.0, "close_time": 3.0},
    )))
    d1, g1 = world.doors
    assert (d1.kind, d1.open_time, d1.close_time, d1.controller) == (
        DoorKind.DOOR, 2.0, 2.0, "simulated")
    assert d1.width == pytest.approx(2.0)
    assert g1.kind is DoorKind.GATE and (g1.open_time, g1.close_time) == (1.0, 3.0)
    # Crossed heading east: the leaf stands north-south, 1.5 m long, centred on (2, 2).
    assert (g1.x1, g1.x2) == pytest.approx((2.0, 2.0))
    assert sorted((g1.y1, g1.y2)) == pytest.approx([1.25, 2.75])
    assert world.door("g1") is g1
    assert g1.distance_to(3.0, 2.0) == pytest.approx(1.0)


@pytest.mark.parametrize(
    ("door", "field", "words"),
    [
        ({"name": "d", "x1": 3.0, "y1": 1.0, "x2": 3.0, "y2": 3.0}, "doors[0].floor",
         "on no floor"),
        ({"name": "d", "floor": "roof", "x1": 3.0, "y1": 1.0, "x2": 3.0, "y2": 3.0},
         "doors[0].floor", "no floor 'roof'"),
        ({"name": "d", "floor": "ground", "x1": 3.0, "y1": 1.0, "x2": 3.0, "y2": 1.0},
         "doors[0].width", "must be > 0"),
        ({"name": "d", "floor": "ground", "x": 2.0, "y": 2.0, "width": 0.0},
         "doors[0].width", "must be > 0"),
        ({"name": "d", "floor": "ground", "x": 2.0, "y": 2.0, "width": -1.0},
         "doors[0].width", "must be > 0"),
        ({"name": "d", "floor": "ground", "x": 2.0, "y": 2.0, "width": 1.0, "kind": "hatch"},
         "doors[0].kind", "not one of"),
        ({"name": "d", "floor": "ground", "x": 2.0, "y": 2.0, "width": 1.0,
          "open_time": 0.0}, "doors[0].open_time", "must be > 0"),
        ({"name": "d", "floor": "ground", "x": 2.0, "y": 2.0, "width": 1.0,
          "controller": "telepathy"}, "doors[0].controller", "not one of"),
    ],
)
def test_a_bad_door_is_refused_with_its_field(tmp_path: Path, door: dict[str, Any],
                                              field: str, words: str) -> None:
    _write(tmp_path, _with_doors(door))
    with pytest.raises(WorldFormatError) as error:
        read_world(tmp_path)
    assert error.value.field == field
    assert words in error.value.reason


def test_door_names_must_not_repeat(tmp_path: Path) -> None:
    door = {"name": "d", "floor": "ground", "x": 2.0, "y": 2.0, "width": 1.0}
    _write(tmp_path, _with_doors(door, dict(door)))
    with pytest.raises(WorldFormatError) as error:
        read_world(tmp_path)
    assert error.value.field == "doors"


def test_a_door_built_in_code_is_checked_too() -> None:
    with pytest.raises(InvalidRequest, match="on no floor"):
        WorldDoor("d", "", 0.0, 0.0, 1.0, 0.0)
    with pytest.raises(InvalidRequest, match="must be > 0"):
        WorldDoor.across("d", "f", 0.0, 0.0, math.pi / 2, 0.0)


def test_the_demo_has_two_fire_doors_on_floor_2_and_a_gate_in_the_lobby() -> None:
    world = load_world("demo")
    by_floor = {(d.floor, d.kind) for d in world.doors}
    assert by_floor == {("floor2", DoorKind.DOOR), ("floor1", DoorKind.GATE)}
    assert sum(d.floor == "floor2" for d in world.doors) == 2
    for door in world.doors:
        # Across a corridor or the lobby's mouth: each end against a wall, the middle free.
        grid = world.floor(door.floor).map
        occupied = grid.occupied()
        info = grid.info
        cx, cy = door.centre
        ix, iy = info.world_to_cell(cx, cy)
        assert not occupied[iy, ix], door.name
        for x, y in ((door.x1, door.y1), (door.x2, door.y2)):
            ex, ey = info.world_to_cell(x, y)
            near = occupied[max(ey - 2, 0):ey + 3, max(ex - 2, 0):ex + 3]
            assert near.any(), (door.name, x, y)


@pytest.mark.parametrize("theta", [0.0, 0.3, math.pi / 4, 1.2, math.pi / 2, 2.5, -0.7, math.pi])
def test_a_door_is_crossed_in_opposite_sectors_from_its_two_sides(theta: float) -> None:
    door = WorldDoor.across("d", "ground", 5.0, 5.0, theta, 1.2)
    ahead = (5.0 + 0.8 * math.cos(theta), 5.0 + 0.8 * math.sin(theta))
    behind = (5.0 - 0.8 * math.cos(theta), 5.0 - 0.8 * math.sin(theta))
    going, coming = door.crossing_flow(*behind), door.crossing_flow(*ahead)
    assert {going, coming} in ({"E", "W"}, {"N", "S"})
    # The sector is the one the crossing heading falls in (away from ties at 45 degrees).
    if abs(abs(math.remainder(theta, math.pi / 2)) - math.pi / 4) > 1e-6:
        assert going == "ENWS"[round(theta / (math.pi / 2)) % 4]


def test_the_demo_fire_door_is_crossed_west_from_the_east() -> None:
    door = load_world("demo").door("fire_door_east")
    assert door.crossing_flow(31.0, 12.0) == "W"
    assert door.crossing_flow(25.0, 11.5) == "E"
