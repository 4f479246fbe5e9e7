"""``polynav run`` serves the Puwei API beside the native one (``--puwei-port``,
``--puwei-discovery-port``, ``--no-puwei``)."""

from __future__ import annotations

import json
import re
import signal
import socket
import subprocess
import sys
import urllib.request
from pathlib import Path

STARTUP_LINES = 20
QUIET = ("--no-yunji", "--no-galileo", "--no-people", "--port", "0")


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
    with urllib.request.urlopen(found[0].group(1) + "/openapi.json", timeout=30):
        pass  # uvicorn handles SIGINT once it answers
    proc.send_signal(signal.SIGINT)
    out, _ = proc.communicate(timeout=60)
    assert proc.returncode == 0
    return out


def test_run_serves_puwei_http_and_discovery_on_the_given_ports(tmp_path: Path) -> None:
    proc = _start(tmp_path, "--puwei-port", "0", "--puwei-discovery-port", "0")
    try:
        lines = _startup(proc)
        found = [m for line in lines if (m := re.search(
            r"Puwei API (http://[\d.]+:(\d+))/api/\S* .*discovery udp (\d+)", line))]
        assert len(found) == 1, lines
        base, http_port, udp_port = found[0].group(1), found[0].group(2), found[0].group(3)
        login = urllib.request.Request(
            base + "/api/user/login", data=b'{"username": "admin", "password": "admin"}',
            headers={"content-type": "application/json"}, method="POST")
        with urllib.request.urlopen(login, timeout=30) as reply:
            token = reply.headers["authorization"]
            assert json.loads(reply.read())["code"] == 0
        status = urllib.request.Request(base + "/api/roslaunch/status",
                                        headers={"authorization": token})
        with urllib.request.urlopen(status, timeout=30) as reply:
            assert json.loads(reply.read()) == {"code": 0, "data": 0, "msg": ""}
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sock:
            sock.settimeout(10.0)
            sock.sendto(b"discovery", ("127.0.0.1", int(udp_port)))
            assert sock.recvfrom(1024)[0] == f"puwei {http_port}".encode()
    finally:
        if proc.poll() is None:
            _stop(proc, lines)


def test_run_without_puwei(tmp_path: Path) -> None:
    proc = _start(tmp_path, "--no-puwei")
    lines = _startup(proc)
    try:
        assert not any("Puwei" in line for line in lines), lines
    finally:
        _stop(proc, lines)


def test_run_with_a_puwei_port_out_of_range_is_a_clear_error(tmp_path: Path) -> None:
    done = subprocess.run(
        [sys.executable, "-m", "polynav", "run", "--data", str(tmp_path / "data"), *QUIET,
         "--puwei-port", "70000"], capture_output=True, text=True, timeout=120)
    assert done.returncode == 2
    assert "puwei.port" in done.stderr and "Traceback" not in done.stderr
