"""``polynav run`` serves the Yunji API beside the native one (``--yunji-port``, ``--no-yunji``,
``--yunji-http-port``, ``--no-yunji-http``)."""

from __future__ import annotations

import json
import re
import urllib.error
import urllib.request
from pathlib import Path

from tests.helpers.polynav_run import start_run, startup_lines, stop_run
from tests.protocols.yunji.conftest import Client


def test_run_serves_yunji_tcp_and_http_on_the_given_ports(tmp_path: Path) -> None:
    proc = start_run(tmp_path, "yunji", "--yunji-port", "0", "--yunji-http-port", "0")
    try:
        lines = startup_lines(proc)
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
        assert "polynav: stopped" in stop_run(proc, lines)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()


def test_run_with_no_yunji_http_serves_tcp_only(tmp_path: Path) -> None:
    proc = start_run(tmp_path, "yunji", "--yunji-port", "0", "--no-yunji-http")
    try:
        lines = startup_lines(proc)
        assert any("Yunji API tcp://" in line for line in lines), lines
        assert not any("Yunji HTTP" in line for line in lines)
        stop_run(proc, lines)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()


def test_run_with_no_yunji_does_not_serve_it(tmp_path: Path) -> None:
    proc = start_run(tmp_path, "yunji", "--no-yunji")
    try:
        lines = startup_lines(proc)
        assert any("Ctrl-C" in line for line in lines), lines
        assert not any("Yunji" in line for line in lines)
        stop_run(proc, lines)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
