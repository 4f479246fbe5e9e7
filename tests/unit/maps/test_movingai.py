from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from polynav.maps.errors import MapFormatError
from polynav.maps.map import FREE, OCCUPIED
from polynav.maps.movingai import Scenario, load_grid, load_map, load_scenarios


def _movingai(data_dir: Path) -> Path:
    return data_dir / "movingai"


def test_load_grid_keeps_movingai_orientation_and_only_dot_is_free(data_dir: Path) -> None:
    grid = load_grid(_movingai(data_dir) / "tunnel.map")
    # tunnel.map rows, first line first: ".@@.", "....", ".@@.", ".@@.", ".@@.", "...."
    # (checked against the file below so a wrong orientation fails loudly).
    text = (_movingai(data_dir) / "tunnel.map").read_text().splitlines()[4:]
    expected = np.array([[c != "." for c in row] for row in text])
    assert grid.dtype == np.bool_
    assert grid.shape == (6, 4)
    assert np.array_equal(grid, expected)
    assert not grid[1].any()


def test_load_grid_treats_trees_as_blocked(data_dir: Path) -> None:
    grid = load_grid(_movingai(data_dir) / "brc202d.map")
    text = (_movingai(data_dir) / "brc202d.map").read_text()
    assert "T" in text
    rows = text.splitlines()[4:]
    row, col = next((r, line.index("T")) for r, line in enumerate(rows) if "T" in line)
    assert grid[row, col]
    assert grid.shape == (481, 530)
    assert int(grid.sum()) == sum(line.count("@") + line.count("T") for line in rows)


@pytest.mark.parametrize(("name", "rows"), [("tree", 5), ("tree2", 12)])
def test_load_grid_counts_rows_present_when_header_height_is_wrong(
    data_dir: Path, name: str, rows: int
) -> None:
    grid = load_grid(_movingai(data_dir) / f"{name}.map")
    assert grid.shape[0] == rows


def test_load_grid_reads_a_last_row_without_trailing_newline(data_dir: Path) -> None:
    path = _movingai(data_dir) / "corners.map"
    assert not path.read_bytes().endswith(b"\n")
    grid = load_grid(path)
    last = path.read_text().splitlines()[-1]
    assert grid.shape == (5, 5)
    assert grid[-1].tolist() == [c != "." for c in last]


def test_load_map_flips_rows_so_the_first_line_is_the_top(data_dir: Path) -> None:
    path = _movingai(data_dir) / "room-32-32-4.map"
    blocked = load_grid(path)
    grid = load_map(path, resolution=0.5)
    assert grid.info.resolution == 0.5
    assert (grid.info.width, grid.info.height) == (32, 32)
    height = blocked.shape[0]
    for row, col in [(0, 0), (3, 7), (31, 12), (15, 31)]:
        expected = OCCUPIED if blocked[row, col] else FREE
        assert grid.data[height - 1 - row, col] == expected
    assert set(np.unique(grid.data).tolist()) == {FREE, OCCUPIED}


def test_load_map_rejects_a_non_positive_resolution(data_dir: Path) -> None:
    with pytest.raises(MapFormatError):
        load_map(_movingai(data_dir) / "tunnel.map", resolution=0.0)


def test_load_scenarios_reads_all_nine_columns(data_dir: Path) -> None:
    scenarios = load_scenarios(_movingai(data_dir) / "brc202d.scen")
    assert len(scenarios) == 2530
    assert scenarios[0] == Scenario(
        bucket=64,
        map_name="brc202d.map",
        width=530,
        height=481,
        start_x=446,
        start_y=403,
        goal_x=444,
        goal_y=182,
        optimal_length=259.12489166,
    )
    assert all(s.has_reference_length for s in scenarios)


def test_load_scenarios_keeps_only_the_base_name_of_an_absolute_map_path(
    data_dir: Path,
) -> None:
    scenarios = load_scenarios(_movingai(data_dir) / "warehouse-20-40-10-2-2.scen")
    assert len(scenarios) == 10000
    assert {s.map_name for s in scenarios} == {"warehouse-20-40-10-2-2.map"}
    assert [s.bucket for s in scenarios[:3]] == [0, 1, 2]
    # Column 9 is all zero and no start equals its goal: no reference lengths here.
    assert not any(s.has_reference_length for s in scenarios)


def test_placeholder_lengths_are_not_reference_lengths_but_start_equals_goal_is(
    data_dir: Path,
) -> None:
    toy = load_scenarios(_movingai(data_dir) / "tree2.scen")
    assert len(toy) == 17
    assert {s.map_name for s in toy} == {"tree.map"}  # a quirk: coordinates fit tree2.map
    assert not any(s.has_reference_length for s in toy)
    maze = load_scenarios(_movingai(data_dir) / "maze-32-32-4.scen")
    same = [s for s in maze if (s.start_x, s.start_y) == (s.goal_x, s.goal_y)]
    assert len(same) == 1
    assert same[0].optimal_length == 0.0 and same[0].has_reference_length


def test_every_scenario_file_fits_the_map_file_of_the_same_name(data_dir: Path) -> None:
    folder = _movingai(data_dir)
    scen_files = sorted(folder.glob("*.scen"))
    assert len(scen_files) == 20
    for scen in scen_files:
        grid = load_grid(scen.with_suffix(".map"))
        height, width = grid.shape
        for s in load_scenarios(scen):
            assert 0 <= s.start_x < width and 0 <= s.goal_x < width, scen.name
            assert 0 <= s.start_y < height and 0 <= s.goal_y < height, scen.name
            assert not grid[s.start_y, s.start_x] and not grid[s.goal_y, s.goal_x], scen.name


def test_load_grid_rejects_a_row_of_the_wrong_width(tmp_path: Path) -> None:
    path = tmp_path / "bad.map"
    path.write_text("type octile\nheight 2\nwidth 3\nmap\n...\n..\n")
    with pytest.raises(MapFormatError, match="row 1"):
        load_grid(path)


def test_load_grid_rejects_a_file_without_map_line(tmp_path: Path) -> None:
    path = tmp_path / "bad.map"
    path.write_text("type octile\nheight 1\nwidth 1\n.\n")
    with pytest.raises(MapFormatError, match="no 'map' line"):
        load_grid(path)


def test_load_scenarios_rejects_a_short_line(tmp_path: Path) -> None:
    path = tmp_path / "bad.scen"
    path.write_text("version 1\n0\tx.map\t3\t3\t0\t0\t1\n")
    with pytest.raises(MapFormatError, match="7 columns"):
        load_scenarios(path)


def test_missing_files_raise_map_format_errors(tmp_path: Path) -> None:
    with pytest.raises(MapFormatError):
        load_grid(tmp_path / "none.map")
    with pytest.raises(MapFormatError):
        load_scenarios(tmp_path / "none.scen")
