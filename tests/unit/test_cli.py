from __future__ import annotations

from pathlib import Path

import pytest

from polynav.cli import main


@pytest.mark.parametrize("argv", [
    ["--help"], ["run", "--help"], ["bench", "--help"], ["map", "--help"],
    ["map", "list", "--help"],
    ["map", "import", "--help"], ["map", "export", "--help"], ["points", "--help"],
    ["points", "list", "--help"], ["points", "add", "--help"], ["points", "rm", "--help"],
    ["fleet", "--help"],
])
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


def test_fleet_needs_a_broker_and_a_positive_speed(
        capsys: pytest.CaptureFixture[str]) -> None:
    for argv in (["fleet"], ["fleet", "--broker", "mqtt://127.0.0.1:1", "--speed", "0"]):
        with pytest.raises(SystemExit) as exit_:
            main(argv)
        assert exit_.value.code == 2
    err = capsys.readouterr().err
    assert "--broker" in err and "must be > 0" in err


def test_run_rejects_a_non_positive_speed(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exit_:
        main(["run", "--speed", "0"])
    assert exit_.value.code == 2
    assert "--speed" in capsys.readouterr().err


@pytest.mark.parametrize("value", ["lagrange", "=http://127.0.0.1:9", "lagrange="])
def test_run_rejects_a_dispatch_server_that_is_not_id_url(
        value: str, capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exit_:
        main(["run", "--dispatch-server", value])
    assert exit_.value.code == 2
    assert "ID=URL" in capsys.readouterr().err


def test_run_refuses_a_dispatch_server_off_loopback(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["run", "--data", str(tmp_path / "d"), "--dispatch-server",
                 "far=http://203.0.113.5/api", "--port", "0"])
    assert code == 2
    assert "dispatch_servers" in capsys.readouterr().err


def test_points_add_list_rm_on_a_data_dir(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    data = ["--data", str(tmp_path)]
    assert main(["points", "add", "desk", "--map", "floor1", "--x", "1.5", "--y", "2", *data]) == 0
    capsys.readouterr()
    assert main(["points", "list", "--map", "floor1", *data]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert "floor1\tdesk\tgeneral\t1.500\t2.000\t0.000" in lines
    assert main(["points", "rm", "desk", *data]) == 0
    assert main(["points", "rm", "desk", *data]) == 1
    assert "not found" in capsys.readouterr().err
    # "initial" is on both demo floors: the map must be named.
    assert main(["points", "rm", "initial", *data]) == 1


def test_map_export_import_list_round_trip(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    data = ["--data", str(tmp_path / "data")]
    out = tmp_path / "out" / "f1.yaml"
    out.parent.mkdir()
    assert main(["map", "export", "floor1", str(out), *data]) == 0
    assert out.is_file() and out.with_suffix(".png").is_file()
    assert main(["map", "import", str(out), "--name", "copy", *data]) == 0
    capsys.readouterr()
    assert main(["map", "list", *data]) == 0
    listed = capsys.readouterr().out
    assert "copy\tfloor=None" in listed
    floor1 = next(line for line in listed.splitlines() if line.startswith("floor1\t"))
    copy = next(line for line in listed.splitlines() if line.startswith("copy\t"))
    assert floor1.split("\t")[2:] == copy.split("\t")[2:]
    assert main(["map", "export", "nothing", str(out), *data]) == 1
