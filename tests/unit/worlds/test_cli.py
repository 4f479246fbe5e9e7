"""``polynav world from-map`` on the command line: a world that loads, or exit code 2 with one
line on stderr and nothing written."""

from __future__ import annotations

from pathlib import Path

import pytest

from polynav.cli import main, site_mismatches
from polynav.store.site_store import SiteStore
from polynav.worlds import load_world
from polynav.worlds.from_map import FromMapOptions, write_world_from_map
from tests.conftest import DATA

NAV2 = DATA / "nav2" / "planner_benchmark" / "100by100_10.yaml"
EMPTY = DATA / "movingai" / "empty-8-8.map"


def test_from_map_writes_a_world_that_loads(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "w"
    assert main(["world", "from-map", str(NAV2), "--out", str(out), "--points", "5",
                 "--walkers", "1", "--seed", "2"]) == 0
    assert "5 points, 1 walkers" in capsys.readouterr().out
    world = load_world(out)
    assert [p.name for p in world.floors[0].points] == ["initial", "p01", "p02", "p03", "p04",
                                                        "p05"]


def _write(folder: Path, name: str, text: str) -> Path:
    path = folder / name
    path.write_text(text)
    return path


BAD = {
    "missing file": (lambda d: d / "none.map", [], "no such file"),
    "malformed MovingAI map": (
        lambda d: _write(d, "bad.map", "type octile\nheight 3\nwidth two\nmap\n...\n"), [],
        "width",
    ),
    "YAML that does not parse": (lambda d: _write(d, "bad.yaml", ": : [\n"), [], "not valid YAML"),
    "ROS map without its image": (
        lambda d: _write(d, "lost.yaml", "image: lost.png\nresolution: 0.05\n"
                         "origin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\n"
                         "free_thresh: 0.196\n"), [], "lost.png",
    ),
    "no free cell": (
        lambda d: _write(d, "solid.map", "type octile\nheight 2\nwidth 2\nmap\n@@\n@@\n"), [],
        "no free space",
    ),
    "more points than fit": (lambda d: EMPTY, ["--points", "500"], "points fit"),
    "a cell of no size": (lambda d: EMPTY, ["--cell", "0"], "cell"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_from_map_refuses_bad_input_with_exit_2_one_line_and_nothing_written(
    case: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    make, extra, reason = BAD[case]
    inputs = tmp_path / "in"
    inputs.mkdir()
    plan = make(inputs)
    out = tmp_path / "out"
    assert main(["world", "from-map", str(plan), "--out", str(out), *extra]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    (line,) = captured.err.splitlines()
    assert line.startswith("polynav world from-map: ") and reason in line
    assert sorted(p.name for p in tmp_path.iterdir()) == ["in"]  # no world, no staging folder


def test_from_map_refuses_an_out_folder_it_cannot_create_with_exit_2_and_no_traceback(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    blocker = _write(tmp_path, "a-file", "not a folder")
    out = blocker / "w"  # its parent is a file: mkdir fails even for root
    assert main(["world", "from-map", str(EMPTY), "--out", str(out), "--points", "2"]) == 2
    (line,) = capsys.readouterr().err.splitlines()
    assert line.startswith(f"polynav world from-map: out: {out}: cannot create it")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a-file"]


def test_run_warns_when_the_site_was_seeded_from_another_world(tmp_path: Path) -> None:
    write_world_from_map(EMPTY, tmp_path / "w", FromMapOptions(points=2, walkers=0))
    generated = load_world(tmp_path / "w")
    with SiteStore.open(tmp_path / "fresh", seed_world=generated) as store:
        assert site_mismatches(store, generated) == []
    with SiteStore.open(tmp_path / "demo", seed_world=load_world("demo")) as store:
        (warning,) = site_mismatches(store, generated)
    assert "map 'floor1' of the site" in warning and "--data NEW_FOLDER" in warning


@pytest.mark.parametrize("argv", [["world", "--help"], ["world", "from-map", "--help"],
                                  ["bench", "nav", "--help"], ["bench", "sim", "--help"]])
def test_the_world_and_bench_commands_have_help(
    argv: list[str], capsys: pytest.CaptureFixture[str]
) -> None:
    with pytest.raises(SystemExit) as exit_:
        main(argv)
    assert exit_.value.code == 0
    assert "usage: polynav" in capsys.readouterr().out
