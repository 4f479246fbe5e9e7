"""``polynav run`` serves Galileo's wire protocols: ``--galileo-serial pty`` prints the pty's
path and shows it in ``GET /api/status``; a host opening it reads status frames and drives the
robot."""

from __future__ import annotations

import json
import re
import time
import urllib.request
from pathlib import Path

import serial

from polynav.protocols.galileo.native import commands as c
from polynav.protocols.galileo.native.status_frame import STATUS_FRAME_SIZE, unpack_status
from tests.helpers.polynav_run import running, stop_run

GALILEO_PORTS = ("--galileo-port", "0", "--galileo-ws-port", "0", "--galileo-udp-port", "0")


def _frames(port: serial.Serial, seconds: float) -> list[dict[str, float]]:
    data = b""
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        data += port.read(max(1, port.in_waiting))
    frames = []
    start = data.find(c.HEADER)
    while start >= 0 and start + STATUS_FRAME_SIZE <= len(data):
        frames.append(unpack_status(data[start:start + STATUS_FRAME_SIZE]))
        start = data.find(c.HEADER, start + STATUS_FRAME_SIZE)
    return frames


def test_run_serves_the_serial_protocol_on_a_pty(tmp_path: Path) -> None:
    with running(tmp_path, "galileo", *GALILEO_PORTS, "--galileo-serial", "pty") as (proc, lines):
        found = [m for line in lines if (m := re.search(r"Galileo serial (/\S+) \(115200 8N1\)",
                                                         line))]
        assert len(found) == 1, lines
        path = found[0].group(1)
        native = next(m.group(1) for line in lines
                      if (m := re.search(r"native API (http://[\d.]+:\d+)", line)))
        with urllib.request.urlopen(native + "/api/status", timeout=30) as reply:
            assert json.loads(reply.read())["links"] == {"galileo_serial": path}
        with serial.Serial(path, 115200, timeout=0.1) as port:
            port.reset_input_buffer()
            port.write(b"garbage" + c.frame(b"\x6d\x01"))  # and m 1, no command
            time.sleep(0.3)
            with urllib.request.urlopen(native + "/api/diagnostics", timeout=30) as reply:
                counts = json.loads(reply.read())["galileo"]
            assert counts["serial.garbage_bytes"] == 7 and counts["native.unknown"] == 1
            frames = _frames(port, 1.0)
            assert 20 <= len(frames) <= 40  # 30 Hz of the real-time simulation
            assert frames[-1]["navStatus"] == 0
            port.write(c.frame(c.start_navigation()))
            deadline = time.monotonic() + 60
            while time.monotonic() < deadline:
                frames = _frames(port, 0.3)
                if frames and frames[-1]["navStatus"] == 1:
                    break
            assert frames and frames[-1]["navStatus"] == 1
        assert "polynav: stopped" in stop_run(proc, lines)


def test_run_serves_modbus_tcp_unless_told_not_to(tmp_path: Path) -> None:
    from pymodbus.client import ModbusTcpClient

    # --galileo-modbus-port 0 comes from the helper
    with running(tmp_path, "galileo", *GALILEO_PORTS) as (proc, lines):
        found = [m for line in lines if (m := re.search(r"Galileo Modbus TCP [\d.]+:(\d+)", line))]
        assert len(found) == 1, lines
        with ModbusTcpClient("127.0.0.1", port=int(found[0].group(1)), timeout=10) as client:
            reply = client.read_discrete_inputs(0, count=2)  # navigation, mapping: both off
            assert not reply.isError() and list(reply.bits[:2]) == [False, False]
        stop_run(proc, lines)
    with running(tmp_path, "galileo", *GALILEO_PORTS, "--no-galileo-modbus") as (proc, lines):
        assert any("Galileo API" in line for line in lines), lines
        assert not any("Modbus" in line for line in lines)
        stop_run(proc, lines)


def test_run_serves_the_udp_fast_protocol(tmp_path: Path) -> None:
    import socket

    # --galileo-udp-fast-port 0 comes from the helper
    with running(tmp_path, "galileo", *GALILEO_PORTS) as (proc, lines):
        found = [m for line in lines
                 if (m := re.search(r"Galileo UDP fast udp://[\d.]+:(\d+)/<topic>", line))]
        assert len(found) == 1, lines
        port = int(found[0].group(1))
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sock:
            sock.settimeout(10)
            sock.sendto(b"\x01udp://127.0.0.1:%d/galileo/status\x00" % port, ("127.0.0.1", port))
            reply, _ = sock.recvfrom(2048)
            assert json.loads(reply[6:])["status"] is True
        stop_run(proc, lines)
