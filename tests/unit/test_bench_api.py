"""``polynav bench api`` runs end to end and prints its figures (no timing is asserted)."""

from __future__ import annotations

import json

import pytest

from polynav.cli import main


def test_bench_api_yunji_prints_rates_and_latencies(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["bench", "api", "--dialect", "yunji", "--clients", "3", "--seconds", "0.3",
                 "--json"]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    assert "commands/s" in lines[1] and "p99 ms" in lines[1]
    assert lines[2].startswith("polynav yunji") and lines[3].startswith("reference:")
    figures = json.loads(lines[-1])
    for row in (figures["polynav"], figures["reference"]):
        assert row["commands_per_second"] > 0.0
        assert 0.0 < row["p50_ms"] <= row["p95_ms"] <= row["p99_ms"]
