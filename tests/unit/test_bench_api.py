"""``polynav bench api`` runs end to end and prints its figures (no timing is asserted)."""

from __future__ import annotations

import json

import pytest

from polynav.cli import main

LOADS = ("GET /api/status keep-alive", "GET /api/status at 200/s", "POST /api/points",
         "yunji robot_status")
FAN_OUT = "WS fan-out x3 at 15 Hz"


def test_bench_api_prints_every_figure_beside_its_reference(
    capsys: pytest.CaptureFixture[str],
) -> None:
    assert main(["bench", "api", "--clients", "3", "--http-clients", "2", "--seconds", "0.4",
                 "--rate", "200", "--ws-clients", "3", "--ws-seconds", "1", "--json"]) == 0
    out = capsys.readouterr().out.strip().splitlines()
    assert "ratio" in out[2] and "p99 ms" in out[2]
    figures = json.loads(out[-1])
    for side in ("polynav", "reference"):
        rows = figures[side]
        assert set(rows) == {*LOADS, FAN_OUT}
        for label in LOADS:
            row = rows[label]
            assert row["per_second"] > 0.0 and row["errors"] == 0, (side, label, row)
            assert 0.0 < row["p50_ms"] <= row["p99_ms"]
        fan_out = rows[FAN_OUT]
        assert fan_out["subscribers"] == 3
        assert fan_out["messages_per_second_min"] > 0.0, (side, fan_out)  # messages flowed
    for label in LOADS:
        assert any(line.startswith(label) for line in out), label


def test_bench_api_refuses_empty_loads(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exit_info:
        main(["bench", "api", "--ws-clients", "0"])
    assert exit_info.value.code == 2
    assert "client counts" in capsys.readouterr().err


def test_bench_api_puwei_logs_in_and_loads_the_status_with_its_token(
    capsys: pytest.CaptureFixture[str],
) -> None:
    assert main(["bench", "api", "--dialect", "puwei", "--http-clients", "2", "--seconds",
                 "0.4", "--ws-clients", "2", "--ws-seconds", "1.5", "--json"]) == 0
    out = capsys.readouterr().out.strip().splitlines()
    figures = json.loads(out[-1])
    for side in ("polynav", "reference"):
        row = figures[side]
        assert row["per_second"] > 0.0 and row["errors"] == 0, (side, row)
    assert any("polynav / reference" in line for line in out)
    assert figures["o_status"]["subscribers"] == 2
    assert figures["o_status"]["messages_per_second_min"] > 0.0


def test_bench_api_rosbridge_counts_subscribed_messages_and_call_latency(
    capsys: pytest.CaptureFixture[str],
) -> None:
    assert main(["bench", "api", "--dialect", "rosbridge", "--clients", "2", "--seconds", "1.5",
                 "--calls", "20", "--json"]) == 0
    out = capsys.readouterr().out.strip().splitlines()
    figures = json.loads(out[-1])
    for side in ("polynav", "reference"):
        row = figures[side]
        assert min(row["messages_per_second_min"].values()) > 0.0, (side, row)
        assert 0.0 < row["get_time_p50_ms"] <= row["get_time_p99_ms"]
    assert any("reference p50" in line for line in out)
