"""``polynav run`` serves rosbridge beside the native API (``--rosbridge-port``,
``--no-rosbridge``)."""

from __future__ import annotations

import json
import re
import subprocess
from pathlib import Path

from tests.helpers.polynav_run import run_args, start_run, startup_lines, stop_run
from tests.protocols.rosbridge.conftest import Client


def test_run_serves_rosbridge_on_the_given_port(tmp_path: Path) -> None:
    proc = start_run(tmp_path, "rosbridge", "--rosbridge-port", "0")
    try:
        lines = startup_lines(proc)
        found = [m for line in lines if (m := re.search(r"rosbridge ws://[\d.]+:(\d+)", line))]
        assert len(found) == 1, lines
        client = Client(int(found[0].group(1)))
        try:
            topics = client.call("/rosapi/topics")["values"]["topics"]
            assert {"/androidmsg_navigationstatus", "/scan", "/galileo/status"} <= set(topics)
            maps = json.loads(client.call("/get_maps")["values"]["message"])
            assert maps["floors"][0]["floorName"] == "floor1"
        finally:
            client.close()
        assert "polynav: stopped" in stop_run(proc, lines)
    finally:
        if proc.poll() is None:
            proc.kill()


def test_no_rosbridge_serves_none(tmp_path: Path) -> None:
    proc = start_run(tmp_path, None)
    try:
        lines = startup_lines(proc)
        assert not any("rosbridge ws:" in line for line in lines), lines
        stop_run(proc, lines)
    finally:
        if proc.poll() is None:
            proc.kill()


def test_a_rosbridge_port_out_of_range_is_a_clear_error(tmp_path: Path) -> None:
    done = subprocess.run(run_args(tmp_path, "rosbridge", "--rosbridge-port", "70000"),
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 2, done.stderr
    assert "rosbridge.port" in done.stderr and "Traceback" not in done.stderr


def test_a_robot_bridge_that_does_not_answer_is_a_clear_error(tmp_path: Path) -> None:
    done = subprocess.run(run_args(tmp_path, None, "--robot-bridge", "http://nowhere"),
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 1, done.stderr
    assert "ros.url" in done.stderr and "Traceback" not in done.stderr
