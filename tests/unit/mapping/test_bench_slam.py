"""``polynav bench slam``: without the public logs it says where to get them; its unseen cases
(logs the simulator records on shipped floor plans the SLAM was never tuned on) are scored."""

from __future__ import annotations

import importlib.util
import json
import math
from pathlib import Path
from types import ModuleType

import pytest

from polynav.cli import main

REPO = Path(__file__).resolve().parents[3]


def _bench() -> ModuleType:
    # Loaded from its file, as ``polynav bench slam`` does (benchmarks are scripts).
    spec = importlib.util.spec_from_file_location("polynav_bench_slam_test",
                                                  REPO / "benchmarks" / "slam.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_bench_slam_without_logs_says_where_to_get_them(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["bench", "slam", "--data", str(tmp_path), "--no-unseen"]) == 2
    out = capsys.readouterr()
    text = out.out + out.err
    assert f"No SLAM logs found in {tmp_path}" in text
    assert "intel.relations" in text and "--data DIR" in text


def test_the_unseen_cases_are_shipped_plans_never_tuned_on() -> None:
    bench = _bench()
    plans = [case.plan for case in bench.UNSEEN_CASES]
    assert len(set(plans)) >= 3
    assert all((REPO / plan).is_file() for plan in plans)
    assert not any("demo" in plan for plan in plans)  # the demo site is what was tuned on
    assert bench.TARGET_UNSEEN == 0.06


def test_a_small_unseen_case_is_recorded_replayed_and_scored_end_to_end() -> None:
    bench = _bench()
    # An 8 x 8 m room, three stops: ~50 s of driving, ~150 scans, the loop closed at the end.
    case = bench.UnseenCase("small", "data/movingai/empty-8-8.map", seed=1, stops=3,
                            time_limit=120.0)
    result = bench.run_unseen_case(case)
    assert result["arrived"] and result["scans"] > 100 and result["skipped_lines"] == 0
    assert result["loop_closures"] > 0 and result["rtf"] > 0.0
    ours, odometry = result["ours"], result["odometry"]
    assert ours["exact"]["relations"] == odometry["exact"]["relations"] > result["scans"] - 1
    assert ours["loops"]["relations"] > 0
    error = ours["exact"]["trans_mean"]
    assert math.isfinite(error) and error <= bench.TARGET_UNSEEN and result["pass"]
    # What the SLAM corrects: on the revisits, the odometry has drifted and the SLAM has not.
    assert ours["loops"]["trans_mean"] < odometry["loops"]["trans_mean"]
    assert ours["loops"]["rot_mean"] < odometry["loops"]["rot_mean"]


def test_an_unseen_plan_that_is_missing_is_a_clear_failure(
    capsys: pytest.CaptureFixture[str]
) -> None:
    bench = _bench()
    bench.UNSEEN_CASES = (bench.UnseenCase("gone", "data/movingai/no-such-plan.map"),)
    assert bench.main(["--unseen-only"]) == 1
    assert "gone: FAIL" in capsys.readouterr().err


def test_without_public_logs_the_unseen_cases_run_and_decide_the_exit_code(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    bench = _bench()
    bench.UNSEEN_CASES = (bench.UnseenCase("small", "data/movingai/empty-8-8.map", seed=1,
                                           stops=2, time_limit=60.0),)
    assert bench.main(["--data", str(tmp_path), "--json"]) == 0
    out = capsys.readouterr()
    assert f"No SLAM logs found in {tmp_path}" in out.err
    assert "only the unseen cases" in out.err
    lines = [json.loads(line) for line in out.out.splitlines() if line.startswith("{")]
    assert [case["name"] for case in lines] == ["small"]
    assert lines[0]["pass"] and "odometry" in lines[0] and "machine" in lines[0]
