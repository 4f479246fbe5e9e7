"""``polynav run`` serves the Galileo API beside the native one (``--galileo-port``,
``--galileo-ws-port``, ``--no-galileo``, ``--galileo-require-token``, ``--galileo-udp-port``)."""

from __future__ import annotations

import json
import re
import signal
import subprocess
import sys
import urllib.error
import urllib.request
from pathlib import Path

import pytest

from polynav.errors import ConfigError
from polynav.protocols.galileo import GalileoConfig

STARTUP_LINES = 20
QUIET = ("--no-yunji", "--no-puwei", "--no-people", "--port", "0")


def _start(tmp_path: Path, *extra: str) -> subprocess.Popen[str]:
    return subprocess.Popen(
        [sys.executable, "-m", "polynav", "run", "--data", str(tmp_path / "data"), *QUIET,
         *extra],
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


def _stop(proc: subprocess.Popen[str], lines: list[str]) -> str:
    found = [m for line in lines if (m := re.search(r"native API (http://[\d.]+:\d+)", line))]
    assert len(found) == 1, lines
    try:  # uvicorn handles SIGINT once it answers
        with urllib.request.urlopen(found[0].group(1) + "/openapi.json", timeout=30):
            pass
    except urllib.error.HTTPError:
        pass
    proc.send_signal(signal.SIGINT)
    out, _ = proc.communicate(timeout=60)
    assert proc.returncode == 0
    return out


def _get(url: str) -> tuple[int, dict[str, object]]:
    try:
        with urllib.request.urlopen(url, timeout=30) as reply:
            return reply.status, json.loads(reply.read())
    except urllib.error.HTTPError as exc:
        return exc.code, json.loads(exc.read())


def test_run_serves_galileo_http_on_the_given_port(tmp_path: Path) -> None:
    proc = _start(tmp_path, "--galileo-port", "0", "--galileo-ws-port", "0",
                  "--galileo-require-token")
    try:
        lines = _startup(proc)
        found = [m for line in lines
                 if (m := re.search(r"Galileo API (http://[\d.]+:\d+)/api/v1", line))]
        assert len(found) == 1, lines
        base = found[0].group(1)
        assert _get(base + "/api/v1/system/status")[0] == 401
        status, body = _get(base + "/token?username=admin&password=admin")
        assert status == 200 and body["result"] is True
        status, body = _get(f"{base}/api/v1/system/status?token={body['token']}")
        assert (status, body) == (200, {"status": "Free"})
        assert "polynav: stopped" in _stop(proc, lines)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()


def test_run_with_no_galileo_does_not_serve_it(tmp_path: Path) -> None:
    proc = _start(tmp_path, "--no-galileo")
    try:
        lines = _startup(proc)
        assert any("Ctrl-C" in line for line in lines), lines
        assert not any("Galileo" in line for line in lines)
        _stop(proc, lines)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()


def test_run_refuses_a_galileo_port_out_of_range_naming_it(tmp_path: Path) -> None:
    proc = subprocess.run(
        [sys.executable, "-m", "polynav", "run", "--data", str(tmp_path / "data"), *QUIET,
         "--galileo-port", "0", "--galileo-ws-port", "0", "--galileo-udp-port", "70000"],
        capture_output=True, text=True, timeout=120,
    )
    assert proc.returncode == 2, proc.stderr
    assert "galileo.udp_port" in proc.stderr and "Traceback" not in proc.stderr


def test_galileo_config_checks_its_ports() -> None:
    assert GalileoConfig(udp_port=0, announce=False).udp_port == 0
    assert GalileoConfig(broadcast_address="192.168.1.255").broadcast_address == "192.168.1.255"
    for bad in ({"udp_port": 0}, {"udp_port": 65536}, {"port": -1}, {"ws_port": 70000},
                {"announce_interval": 0.0}, {"host": ""}, {"broadcast_address": "lan"},
                {"broadcast_address": ""}):
        with pytest.raises(ConfigError) as refused:
            GalileoConfig(**bad)  # type: ignore[arg-type]
        assert refused.value.key.startswith("galileo.")
