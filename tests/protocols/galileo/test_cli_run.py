"""``polynav run`` serves the Galileo API beside the native one (``--galileo-port``,
``--galileo-ws-port``, ``--no-galileo``, ``--galileo-require-token``, ``--galileo-udp-port``)."""

from __future__ import annotations

import json
import re
import subprocess
import urllib.error
import urllib.request
from pathlib import Path

import pytest

from polynav.errors import ConfigError
from polynav.protocols.galileo import GalileoConfig
from tests.helpers.polynav_run import run_args, start_run, startup_lines, stop_run


def _get(url: str) -> tuple[int, dict[str, object]]:
    try:
        with urllib.request.urlopen(url, timeout=30) as reply:
            return reply.status, json.loads(reply.read())
    except urllib.error.HTTPError as exc:
        return exc.code, json.loads(exc.read())


def test_run_serves_galileo_http_on_the_given_port(tmp_path: Path) -> None:
    proc = start_run(tmp_path, "galileo", "--galileo-port", "0", "--galileo-ws-port", "0",
                  "--galileo-require-token")
    try:
        lines = startup_lines(proc)
        found = [m for line in lines
                 if (m := re.search(r"Galileo API (http://[\d.]+:\d+)/api/v1", line))]
        assert len(found) == 1, lines
        base = found[0].group(1)
        assert _get(base + "/api/v1/system/status")[0] == 401
        status, body = _get(base + "/token?username=admin&password=admin")
        assert status == 200 and body["result"] is True
        status, body = _get(f"{base}/api/v1/system/status?token={body['token']}")
        assert (status, body) == (200, {"status": "Free"})
        assert "polynav: stopped" in stop_run(proc, lines)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()


def test_run_with_no_galileo_does_not_serve_it(tmp_path: Path) -> None:
    proc = start_run(tmp_path, "galileo", "--no-galileo")
    try:
        lines = startup_lines(proc)
        assert any("Ctrl-C" in line for line in lines), lines
        assert not any("Galileo" in line for line in lines)
        stop_run(proc, lines)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()


def test_run_refuses_a_galileo_port_out_of_range_naming_it(tmp_path: Path) -> None:
    proc = subprocess.run(
        run_args(tmp_path, "galileo", "--galileo-port", "0", "--galileo-ws-port", "0",
                 "--galileo-udp-port", "70000"),
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
