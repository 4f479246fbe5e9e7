"""``polynav bench sim`` over seeds with walkers, and ``polynav bench nav`` over MovingAI maps,
end to end on small worlds (no timing is asserted)."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from polynav.cli import main
from polynav.worlds.from_map import FromMapOptions, write_world_from_map
from tests.conftest import DATA

SMALL = DATA / "movingai" / "empty-8-8.map"


def _last_json(out: str) -> dict[str, object]:
    return json.loads(out.strip().splitlines()[-1])


def test_bench_sim_runs_seeds_with_walkers_on_any_world(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    write_world_from_map(SMALL, tmp_path / "w", FromMapOptions(points=2, walkers=1, seed=1))
    assert main(["bench", "sim", "--world", str(tmp_path / "w"), "--seeds", "2", "--json"]) == 0
    figures = _last_json(capsys.readouterr().out)
    assert figures["seeds"] == [0, 1] and figures["people"] is True
    assert figures["goals"] == 6  # the initial point and two goals, twice
    assert 0.0 <= figures["success_rate"] <= 1.0  # type: ignore[operator]
    assert figures["real_time_factor"] > 0.0  # type: ignore[operator]


def test_bench_nav_prints_per_map_and_overall(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    shutil.copy(SMALL, tmp_path / SMALL.name)
    (tmp_path / "huge.map").write_text("type octile\nheight 300\nwidth 300\nmap\n"
                                       + ("." * 300 + "\n") * 300)
    assert main(["bench", "nav", "--maps", str(tmp_path), "--goals", "2", "--walkers", "1",
                 "--json"]) == 0
    out = capsys.readouterr().out
    figures = _last_json(out)
    (row,) = figures["maps"]  # type: ignore[misc]
    assert row["map"] == "empty-8-8.map" and row["goals"] == 2  # 300 x 300 is left out
    overall = figures["overall"]
    assert set(overall) >= {"success_rate", "path_efficiency_median", "collisions",  # type: ignore[arg-type]
                            "closest_person_m", "real_time_factor_min"}
    assert "overall:" in out


def test_bench_nav_without_maps_fails_clearly(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["bench", "nav", "--maps", str(tmp_path / "none")]) == 2
    assert "no MovingAI maps" in capsys.readouterr().err
