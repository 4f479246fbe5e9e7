"""``polynav run`` serves the Yunji API beside the native one (``--yunji-port``, ``--no-yunji``,
``--yunji-http-port``, ``--no-yunji-http``)."""

from __future__ import annotations

import json
import re
import signal
import subprocess
import sys
import urllib.error
import urllib.request
from pathlib import Path

from tests.protocols.yunji.conftest import Client

STARTUP_LINES = 20


def _start(tmp_path: Path, *extra: str) -> subprocess.Popen[str]:
    return subprocess.Popen(
        [sys.executable, "-m", "polynav", "run", "--data", str(tmp_path / "data"),
         "--port", "0", "--no-people", "--no-puwei", "--no-galileo", *extra],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )


def _startup(proc: subprocess.Popen[str]) -> list[str]:
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


def _wait_serving(lines: list[str]) -> None:
    """An HTTP answer from the native API: uvicorn runs and handles SIGINT from now on (a SIGINT
    sent earlier, between ``run``'s own handler and uvicorn's, would be logged and ignored)."""
    found = [m for line in lines if (m := re.search(r"native API (http://[\d.]+:\d+)", line))]
    assert len(found) == 1, lines
    try:
        with urllib.request.urlopen(found[0].group(1) + "/openapi.json", timeout=30) as reply:
            assert reply.status == 200
    except urllib.error.HTTPError as exc:  # any HTTP answer will do
        assert exc.code > 0


def _stop(proc: subprocess.Popen[str], lines: list[str]) -> str:
    _wait_serving(lines)
    proc.send_signal(signal.SIGINT)
    out, _ = proc.communicate(timeout=60)
    assert proc.returncode == 0
    return out


def test_run_serves_yunji_tcp_and_http_on_the_given_ports(tmp_path: Path) -> None:
    proc = _start(tmp_path, "--yunji-port", "0", "--yunji-http-port", "0")
    try:
        lines = _startup(proc)
        found = [m for line in lines if (m := re.search(r"Yunji API tcp://[\d.]+:(\d+)", line))]
        assert len(found) == 1, lines
        client = Client(int(found[0].group(1)))
        try:
            assert client.request("/api/robot_info")["status"] == "OK"
            assert client.request("/api/robot_status")["results"]["current_floor"] == 1
        finally:
            client.close()
        http = [m for line in lines if (m := re.search(r"Yunji HTTP (http://[\d.]+:\d+)", line))]
        assert len(http) == 1, lines
        with urllib.request.urlopen(http[0].group(1) + "/api/robot_info", timeout=30) as reply:
            assert json.loads(reply.read())["status"] == "OK"
        assert "polynav: stopped" in _stop(proc, lines)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()


def test_run_with_no_yunji_http_serves_tcp_only(tmp_path: Path) -> None:
    proc = _start(tmp_path, "--yunji-port", "0", "--no-yunji-http")
    try:
        lines = _startup(proc)
        assert any("Yunji API tcp://" in line for line in lines), lines
        assert not any("Yunji HTTP" in line for line in lines)
        _stop(proc, lines)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()


def test_run_with_no_yunji_does_not_serve_it(tmp_path: Path) -> None:
    proc = _start(tmp_path, "--no-yunji")
    try:
        lines = _startup(proc)
        assert any("Ctrl-C" in line for line in lines), lines
        assert not any("Yunji" in line for line in lines)
        _stop(proc, lines)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
