from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import pytest
import yaml

from polynav.errors import InvalidRequest
from polynav.geometry import Pose2D
from polynav.maps.ascii import map_from_ascii
from polynav.maps.errors import MapFormatError
from polynav.maps.ros_map import save_map
from polynav.site import PointKind
from polynav.worlds import builtin_worlds, load_world
from polynav.worlds.errors import WorldFormatError
from polynav.worlds.world import LiftShaft, PersonRoute
from polynav.worlds.world_file import read_world

GROUND = """
    ######
    #....#
    #....#
    ######
"""


def _document() -> dict[str, Any]:
    return {
        "name": "tiny",
        "start": {"floor": "ground", "pose": {"x": 1.5, "y": 1.5, "theta": 0.5}},
        "floors": [{
            "name": "ground",
            "level": 0,
            "map": "ground.yaml",
            "lift": {"x": 4.0, "y": 2.0, "width": 1.0, "depth": 1.5},
            "points": [
                {"name": "home", "x": 1.5, "y": 1.5, "theta": 0.5, "kind": "initial"},
                {"name": "dock", "x": 4.5, "y": 2.5, "theta": math.pi, "kind": "charger",
                 "number": 7},
                {"name": "spot", "x": 2.5, "y": 2.5},
            ],
            "people": [{"waypoints": [[1.5, 2.5], [4.5, 2.5]], "speed": 0.5, "loop": False}],
            "access_points": [
                {"ssid": "lab", "x": 1.0, "y": 1.0, "frequency": 5180, "security": "WPA2",
                 "password": "pw"},
                {"ssid": "open", "x": 3.0, "y": 1.0},
            ],
        }],
    }


def _write(folder: Path, doc: dict[str, Any]) -> Path:
    folder.mkdir(exist_ok=True)
    save_map(map_from_ascii(GROUND, resolution=1.0), folder / "ground.yaml")
    (folder / "world.yaml").write_text(yaml.safe_dump(doc), encoding="utf-8")
    return folder


def test_world_folder_loads_floors_points_lift_and_people(tmp_path: Path) -> None:
    world = read_world(_write(tmp_path / "tiny", _document()))
    assert world.name == "tiny"
    assert world.start_floor == "ground"
    assert world.start_pose == Pose2D(1.5, 1.5, 0.5)
    floor = world.floor("ground")
    assert (floor.level, floor.map_name) == (0, "ground")
    assert floor.map.occupied().sum() == 16
    assert floor.lift == LiftShaft(x=4.0, y=2.0, width=1.0, depth=1.5, door_heading=0.0,
                                   door_width=1.2)
    assert [(p.name, p.kind, p.number) for p in floor.points] == [
        ("home", PointKind.INITIAL, None), ("dock", PointKind.CHARGER, 7),
        ("spot", PointKind.GENERAL, None),
    ]
    assert floor.point("dock").pose == Pose2D(4.5, 2.5, math.pi)
    assert floor.people == (
        PersonRoute(waypoints=((1.5, 2.5), (4.5, 2.5)), speed=0.5, radius=0.25, loop=False),
    )


def test_access_points_are_read_with_their_defaults(tmp_path: Path) -> None:
    floor = read_world(_write(tmp_path / "tiny", _document())).floors[0]
    assert [(a.ssid, a.frequency, a.security, a.password) for a in floor.access_points] == [
        ("lab", 5180, "WPA2", "pw"), ("open", 2412, "", "")]


def test_load_world_takes_a_folder_path(tmp_path: Path) -> None:
    folder = _write(tmp_path / "tiny", _document())
    assert load_world(folder).name == "tiny"
    assert load_world(str(folder)).name == "tiny"


def test_demo_is_a_builtin_world() -> None:
    assert "demo" in builtin_worlds()


def test_unknown_builtin_name_is_an_invalid_request() -> None:
    with pytest.raises(InvalidRequest) as error:
        load_world("no_such_world")
    assert error.value.field == "world"
    assert "demo" in error.value.reason


def test_missing_world_file_is_a_format_error(tmp_path: Path) -> None:
    with pytest.raises(WorldFormatError) as error:
        read_world(tmp_path)
    assert error.value.field == "world.yaml"


def test_missing_map_file_is_a_map_format_error(tmp_path: Path) -> None:
    doc = _document()
    doc["floors"][0]["map"] = "cellar.yaml"
    _write(tmp_path, doc)
    with pytest.raises(MapFormatError):
        read_world(tmp_path)


def _break(doc: dict[str, Any], path: str, value: object) -> dict[str, Any]:
    *keys, last = path.split(".")
    node: Any = doc
    for key in keys:
        node = node[int(key)] if key.isdigit() else node[key]
    node[int(last) if last.isdigit() else last] = value
    return doc


@pytest.mark.parametrize(
    ("path", "value", "field"),
    [
        ("start.floor", "roof", "start.floor"),
        ("floors.0.points.1.kind", "helipad", "floors[0].points[1].kind"),
        ("floors.0.points.0.x", "left", "floors[0].points[0].x"),
        ("floors.0.points.2.name", "home", "floors[0].points"),
        ("floors.0.level", 1.5, "floors[0].level"),
        ("floors.0.lift.width", 0.0, "floors[0].lift.width"),
        ("floors.0.people.0.speed", -1.0, "floors[0].people[0].speed"),
        ("floors.0.people.0.waypoints", [[1.0, 2.0, 3.0]], "floors[0].people[0].waypoints[0]"),
        ("floors.0.access_points.0.frequency", 900, "floors[0].access_points[0].frequency"),
        ("floors.0.access_points.0.frequency", "2.4G", "floors[0].access_points[0].frequency"),
        ("floors.0.access_points.0.password", "", "floors[0].access_points[0].password"),
        ("floors.0.access_points.1.ssid", "", "floors[0].access_points[1].ssid"),
        ("floors.0.access_points.1.security", 3, "floors[0].access_points[1].security"),
        ("floors", [], "floors"),
    ],
)
def test_invalid_field_is_named_in_the_error(
    tmp_path: Path, path: str, value: object, field: str
) -> None:
    _write(tmp_path, _break(_document(), path, value))
    with pytest.raises(WorldFormatError) as error:
        read_world(tmp_path)
    assert error.value.field == field
