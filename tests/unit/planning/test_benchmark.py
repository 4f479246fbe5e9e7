"""The planner benchmark script runs end to end on a tiny folder and reports its figures."""

from __future__ import annotations

import importlib.util
import json
import shutil
from pathlib import Path
from types import ModuleType

import pytest

from tests.conftest import REPO


def _load_benchmark() -> ModuleType:
    # Loaded from its file, as ``polynav bench planner`` does (benchmarks are scripts).
    spec = importlib.util.spec_from_file_location("planner_benchmark", REPO / "benchmarks" /
                                                  "planner.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_planner_benchmark_emits_its_figures_as_one_json_line(
    data_dir: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    pytest.importorskip("pyastar2d")
    pytest.importorskip("skimage")
    for name in ("maze-32-32-4", "room-32-32-4"):
        for suffix in (".map", ".scen"):
            shutil.copy(data_dir / "movingai" / f"{name}{suffix}", tmp_path)
    bench = _load_benchmark()
    code = bench.main(["--maps", str(tmp_path), "--limit", "2", "--no-nav2", "--json"])
    assert code == 0
    last = capsys.readouterr().out.strip().splitlines()[-1]
    figures = json.loads(last)
    keys = {"queries", "cost_mismatches", "median_ms", "p95_ms", "ratio_vs_pyastar2d"}
    assert keys | {"sets", "commit", "machine", "skimage_queries"} <= set(figures)
    assert figures["queries"] == 4
    assert figures["cost_mismatches"] == 0
    assert set(figures["median_ms"]) == {"polynav", "pyastar2d", "skimage"}
    assert all(v is not None and v > 0 for v in figures["median_ms"].values())
    assert set(figures["sets"]) == {"movingai"}
    assert keys <= set(figures["sets"]["movingai"])
    assert figures["sets"]["movingai"]["queries"] == 4
    assert figures["skimage_queries"] == 4
    assert isinstance(figures["machine"], str)


def test_planner_benchmark_fails_clearly_without_maps(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    bench = _load_benchmark()
    assert bench.main(["--maps", str(tmp_path / "nonexistent"), "--no-nav2"]) == 2
    err = capsys.readouterr().err
    assert "no MovingAI .scen/.map pairs" in err and "nonexistent" in err


def test_planner_benchmark_fails_clearly_without_nav2_maps(
    data_dir: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    bench = _load_benchmark()
    code = bench.main(["--maps", str(data_dir / "movingai"), "--nav2-dir", str(tmp_path)])
    assert code == 2
    assert "none of the Nav2 maps" in capsys.readouterr().err
