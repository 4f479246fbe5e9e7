"""``polynav run`` serves the Puwei API beside the native one (``--puwei-port``,
``--puwei-discovery-port``, ``--no-puwei``)."""

from __future__ import annotations

import json
import re
import socket
import subprocess
import urllib.request
from pathlib import Path

from tests.helpers.polynav_run import run_args, start_run, startup_lines, stop_run


def test_run_serves_puwei_http_and_discovery_on_the_given_ports(tmp_path: Path) -> None:
    proc = start_run(tmp_path, "puwei", "--puwei-port", "0", "--puwei-discovery-port", "0")
    try:
        lines = startup_lines(proc)
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
            stop_run(proc, lines)


def test_run_without_puwei(tmp_path: Path) -> None:
    proc = start_run(tmp_path, "puwei", "--no-puwei")
    lines = startup_lines(proc)
    try:
        assert not any("Puwei" in line for line in lines), lines
    finally:
        stop_run(proc, lines)


def test_run_with_a_puwei_port_out_of_range_is_a_clear_error(tmp_path: Path) -> None:
    done = subprocess.run(
        run_args(tmp_path, "puwei", "--puwei-port", "70000"), capture_output=True, text=True,
        timeout=120)
    assert done.returncode == 2
    assert "puwei.port" in done.stderr and "Traceback" not in done.stderr
