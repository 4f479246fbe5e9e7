"""``--robot`` on the command line: a bad profile stops ``polynav run`` at start-up with exit 2
and the field named; ``world from-map --robot`` writes a world for that robot; ``world.yaml``'s
``robot:`` entry loads or names the profile's field at fault."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
import yaml

from polynav.cli import main
from polynav.worlds import load_world
from polynav.worlds.errors import WorldFormatError
from tests.conftest import DATA

NAV2 = DATA / "nav2" / "planner_benchmark" / "100by100_10.yaml"

BAD_PROFILES = {
    "negative speed": ({"limits": {"max_linear_velocity": -1}}, "robot.limits.max_linear_velocity"),
    "self-intersecting polygon": (
        {"footprint": {"polygon": [[0.3, 0.2], [-0.2, -0.2], [-0.2, 0.2], [0.3, -0.2]]}},
        "robot.footprint.polygon",
    ),
    "lidar off the body": ({"lidar": {"pose": {"x": 0.6}}}, "robot.lidar.pose"),
    "unknown key": ({"wheels": 4}, "robot.wheels"),
}


def _profile(tmp_path: Path, changes: dict[str, object]) -> Path:
    doc: dict[str, object] = {"name": "bad", "footprint": {"radius": 0.2}}
    doc.update(changes)
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump(doc))
    return path


@pytest.mark.parametrize("case", sorted(BAD_PROFILES))
def test_run_with_a_bad_profile_exits_2_naming_the_field(
    case: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    changes, field = BAD_PROFILES[case]
    path = _profile(tmp_path, changes)
    code = main(["run", "--robot", str(path), "--data", str(tmp_path / "data"), "--port", "0"])
    err = capsys.readouterr().err
    assert code == 2
    assert field in err and err.count("\n") == 1
    assert not (tmp_path / "data").exists()  # refused before anything was written


def test_run_with_an_unknown_builtin_exits_2(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["run", "--robot", "hovercraft", "--data", str(tmp_path / "d")]) == 2
    assert "research-base" in capsys.readouterr().err  # the built-ins are listed


def test_from_map_with_a_robot_writes_it_into_the_world(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "w"
    assert main(["world", "from-map", str(NAV2), "--out", str(out), "--points", "3",
                 "--walkers", "0", "--robot", "research-base"]) == 0
    world = load_world(out)
    assert world.robot is not None and world.robot.name == "research-base"
    assert world.robot.footprint.vertices.shape == (4, 2)


def test_from_map_with_a_bad_robot_exits_2_and_writes_nothing(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = _profile(tmp_path, {"limits": {"max_linear_velocity": -1}})
    out = tmp_path / "w"
    assert main(["world", "from-map", str(NAV2), "--out", str(out), "--robot", str(path)]) == 2
    assert "robot.limits.max_linear_velocity" in capsys.readouterr().err
    assert not out.exists()


def _world_with_robot(tmp_path: Path, robot: object) -> Path:
    demo = Path(__file__).resolve().parents[3] / "polynav" / "worlds" / "demo"
    folder = tmp_path / "world"
    shutil.copytree(demo, folder)
    doc = yaml.safe_load((folder / "world.yaml").read_text())
    doc["robot"] = robot
    (folder / "world.yaml").write_text(yaml.safe_dump(doc))
    return folder


def test_world_robot_entry_by_name_by_file_and_inline(tmp_path: Path) -> None:
    assert load_world(_world_with_robot(tmp_path / "a", "delivery")).robot.name == "delivery"
    folder = _world_with_robot(tmp_path / "b", "mine.yaml")
    (folder / "mine.yaml").write_text(yaml.safe_dump({"name": "mine",
                                                      "footprint": {"radius": 0.3}}))
    assert load_world(folder).robot.inscribed_radius == pytest.approx(0.3)
    inline = {"name": "inline", "footprint": {"radius": 0.22}}
    assert load_world(_world_with_robot(tmp_path / "c", inline)).robot.name == "inline"


def test_world_robot_entry_at_fault_names_the_field(tmp_path: Path) -> None:
    bad = {"name": "x", "footprint": {"radius": 0.2}, "limits": {"linear_acceleration": -2}}
    with pytest.raises(WorldFormatError) as err:
        load_world(_world_with_robot(tmp_path, bad))
    assert err.value.field == "robot.limits.linear_acceleration"
