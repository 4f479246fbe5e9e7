"""``polynav bench sim`` over seeds with walkers, and ``polynav bench nav`` over MovingAI maps,
end to end on small worlds (no timing is asserted)."""

from __future__ import annotations

import importlib.util
import json
import shutil
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest

from polynav.cli import main
from polynav.worlds.from_map import FromMapOptions, write_world_from_map
from tests.conftest import DATA

SMALL = DATA / "movingai" / "empty-8-8.map"


def _load_bench_nav() -> ModuleType:
    path = Path(__file__).resolve().parents[2] / "benchmarks" / "nav.py"
    spec = importlib.util.spec_from_file_location("polynav_bench_nav_test", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


bench_nav = _load_bench_nav()


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
    assert 0.0 <= figures["worst_final_error_m"] < 0.5  # type: ignore[operator]


def test_bench_sim_prints_the_worst_final_error_beside_the_success_count(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    write_world_from_map(SMALL, tmp_path / "w", FromMapOptions(points=2, walkers=0, seed=1))
    assert main(["bench", "sim", "--world", str(tmp_path / "w"), "--no-people", "--json"]) == 0
    out = capsys.readouterr().out
    figures = _last_json(out)
    worst = figures["worst_final_error_m"]
    goal_errors = [float(line.split("err=")[1].split("m")[0]) for line in out.splitlines()
                   if " ok " in line and "err=" in line]
    assert len(goal_errors) == figures["succeeded"]
    assert worst == pytest.approx(max(goal_errors), abs=6e-4)
    assert f"succeeded {figures['succeeded']} (worst final error {worst * 100:.1f} cm)" in out


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
    assert figures["left_out"] == ["huge.map: 300 x 300 cells, more than 256"]
    assert row["reached"] + sum(row["failures"].values()) == 2
    outcomes = row["outcomes"]
    assert [o["goal"] for o in outcomes] == ["p01", "p02"]
    assert sum(o["outcome"] == "reached" for o in outcomes) == row["reached"]
    assert {"closest_person_m", "closest_person_approached_m", "seconds"} <= set(outcomes[0])
    reached = [o["final_error_m"] for o in outcomes if o["outcome"] == "reached"]
    assert row["worst_final_error_m"] == max(reached, default=0.0)
    assert row["real_time_factor"] > 0.0 and row["real_time_factor_wall"] > 0.0
    overall = figures["overall"]
    assert set(overall) >= {"success_rate", "path_efficiency_median", "collisions",  # type: ignore[arg-type]
                            "closest_person_m", "real_time_factor_min", "targets", "pass"}
    assert "overall:" in out
    assert overall["worst_final_error_m"] == row["worst_final_error_m"]  # type: ignore[index]
    assert "worst final error" in out


def _row(reached: int, efficiencies: list[float], closest: float | None, rtf: float,
         failures: dict[str, int] | None = None,
         approached: float | None = None) -> dict[str, Any]:
    return {"goals": 4, "reached": reached, "path_efficiencies": efficiencies,
            "failures": failures or {}, "collisions": 0, "closest_person_m": closest,
            "closest_person_approached_m": closest if approached is None else approached,
            "real_time_factor": rtf, "sim_seconds": 10.0,
            "goals_with_localization_lost": 0, "worst_final_error_m": 0.01 * reached}


def test_overall_figures_pool_every_goal_and_name_the_missed_targets() -> None:
    rows = [_row(4, [1.1, 1.2, 1.2, 1.25], 1.0, 30.0),
            _row(3, [1.2, 1.4, 2.0], None, 25.0, {"timeout": 1})]
    overall = bench_nav.overall_figures(rows, social_distance=0.8)
    assert (overall["goals"], overall["reached"], overall["success_rate"]) == (8, 7, 0.875)
    assert overall["path_efficiency_median"] == 1.2  # the 4th of 7 goals reached, in order
    assert overall["failures"] == {"timeout": 1}
    assert overall["closest_person_m"] == 1.0 and overall["real_time_factor_min"] == 25.0
    assert overall["missed"] == ["success_rate"] and overall["pass"] is False
    near = bench_nav.overall_figures([_row(4, [1.0], 0.5, 10.0)], social_distance=0.8)
    assert near["missed"] == ["closest_person", "real_time_factor"]


def test_social_distance_is_judged_on_approaches_the_robot_made() -> None:
    # A walker passed a standing robot at 0.5 m; the robot itself never closed in within 0.9 m.
    passed = bench_nav.overall_figures([_row(4, [1.0], 0.5, 30.0, approached=0.9)],
                                       social_distance=0.8)
    assert passed["closest_person_m"] == 0.5 and passed["closest_person_approached_m"] == 0.9
    assert passed["missed"] == [] and passed["pass"] is True
    pushed = bench_nav.overall_figures([_row(4, [1.0], 0.5, 30.0, approached=0.6)],
                                       social_distance=0.8)
    assert pushed["missed"] == ["closest_person"]


def test_bench_nav_without_maps_fails_clearly(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["bench", "nav", "--maps", str(tmp_path / "none")]) == 2
    assert "no MovingAI maps" in capsys.readouterr().err
