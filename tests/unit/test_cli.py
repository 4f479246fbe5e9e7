from __future__ import annotations

import threading

import pytest

from polynav.cli import main
from polynav.runtime.demo_tour import run_demo_tour
from polynav.worlds import load_world


@pytest.mark.parametrize("argv", [["--help"], ["run", "--help"], ["bench", "--help"]])
def test_every_command_has_help(argv: list[str], capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exit_:
        main(argv)
    assert exit_.value.code == 0
    assert "usage: polynav" in capsys.readouterr().out


def test_unknown_bench_area_is_a_usage_error(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exit_:
        main(["bench", "nothing"])
    assert exit_.value.code == 2
    assert "invalid choice" in capsys.readouterr().err


def test_run_rejects_a_non_positive_speed(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["run", "--speed", "0"]) == 2
    assert "--speed" in capsys.readouterr().err


def test_demo_tour_reaches_its_first_goal_and_stops_when_told() -> None:
    stop = threading.Event()
    lines: list[str] = []

    def report(line: str) -> None:
        lines.append(line)
        if "reached goal" in line:
            stop.set()

    reached = run_demo_tour(load_world("demo"), speed=1e6, seed=0, people=False, stop=stop,
                            report=report)
    assert reached == 1
    assert lines[0].strip().startswith("t=")
    assert "heading to" in lines[0]
    assert any("reached goal 1" in line for line in lines)
