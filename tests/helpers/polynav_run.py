"""``polynav run`` as a user starts it, for the tests of its command line: one dialect served
(the others off, so tests running side by side never meet on a default port), its start-up
lines read, and a clean stop by SIGINT."""

from __future__ import annotations

import contextlib
import re
import signal
import subprocess
import sys
import urllib.error
import urllib.request
from collections.abc import Iterator
from pathlib import Path

STARTUP_LINES = 20
#: Every dialect `polynav run` serves by default, and the flag that turns it off.
DIALECTS = {"yunji": "--no-yunji", "galileo": "--no-galileo", "puwei": "--no-puwei",
            "rosbridge": "--no-rosbridge"}


#: The Galileo wires with a default port, on any free port (``extra`` may say otherwise).
GALILEO_WIRES = ("--galileo-modbus-port", "0", "--galileo-udp-fast-port", "0")


def run_args(tmp_path: Path, dialect: str | None, *extra: str) -> list[str]:
    """The command line: a fresh site under ``tmp_path``, only ``dialect`` served (``None``:
    none), no walkers, the native API (and Galileo's wires) on any free port."""
    off = [flag for name, flag in DIALECTS.items() if name != dialect]
    wires = GALILEO_WIRES if dialect == "galileo" else ()
    return [sys.executable, "-m", "polynav", "run", "--data", str(tmp_path / "data"), *off,
            "--no-people", "--port", "0", *wires, *extra]


def start_run(tmp_path: Path, dialect: str | None, *extra: str) -> subprocess.Popen[str]:
    return subprocess.Popen(run_args(tmp_path, dialect, *extra),
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def startup_lines(proc: subprocess.Popen[str]) -> list[str]:
    """What it printed up to "Ctrl-C to stop" (or its exit)."""
    assert proc.stdout is not None
    lines: list[str] = []
    while len(lines) < STARTUP_LINES:
        line = proc.stdout.readline()
        if not line:
            break
        lines.append(line.rstrip("\n"))
        if "Ctrl-C" in line:
            break
    return lines


def stop_run(proc: subprocess.Popen[str], lines: list[str]) -> str:
    """Wait until the native API answers (uvicorn handles SIGINT from then on), send SIGINT,
    check the clean exit and return the rest of standard output."""
    found = [m for line in lines if (m := re.search(r"native API (http://[\d.]+:\d+)", line))]
    assert len(found) == 1, lines
    try:
        with urllib.request.urlopen(found[0].group(1) + "/docs", timeout=30):
            pass
    except urllib.error.HTTPError:  # any HTTP answer will do
        pass
    proc.send_signal(signal.SIGINT)
    out, _ = proc.communicate(timeout=60)
    assert proc.returncode == 0
    return out


@contextlib.contextmanager
def running(tmp_path: Path, dialect: str | None, *extra: str
            ) -> Iterator[tuple[subprocess.Popen[str], list[str]]]:
    """``polynav run`` started, its start-up lines read; killed at the end if the test did not
    stop it (``stop_run``)."""
    proc = start_run(tmp_path, dialect, *extra)
    try:
        yield proc, startup_lines(proc)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
