"""Galileo's UDP fast protocol (galileo-wire-protocols §4) over real UDP sockets on 127.0.0.1.

The client below is written from spec §4 alone, as the C# and TypeScript example clients
behave (§5.1, §5.2): a connection frame ``01 + udp://...?token= + 00``, the reply's JSON read from
byte 6, data frames ``02 + id + opcode`` (BINARY with a little-endian package_index), a PONG for
every PING, and received datagrams with another marker or id dropped. Long messages from the
robot arrive as BINARY chunks ended by a shorter one (docs/decisions.md, "Galileo UDP fast
protocol"), which the client joins. Simulated time is advanced by the test (the runtime's loop
thread is not started).
"""

from __future__ import annotations

import json
import math
import random
import socket
import struct
import threading
import time
from collections.abc import Iterator
from typing import Any

import pytest

from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.diagnostics import diagnostics
from polynav.protocols.galileo.native import commands as c
from polynav.protocols.galileo.native.ros_message import encode_native_cmds
from polynav.protocols.galileo.status import galileo_status
from polynav.protocols.galileo.udp_fast import UdpFastListener
from polynav.runtime.robot_runtime import RobotRuntime
from tests.helpers.loop_thread import LoopThread
from tests.helpers.wire_fuzz import garbage, tracebacks
from tests.protocols.galileo import spec
from tests.protocols.galileo.conftest import Harness, galileo_config, serving
from tests.protocols.galileo.test_status import FIELDS

COVERED = {
    "galileo-udp cmd 0x01 connect": "test_registration_and_refusals",
    "galileo-udp cmd connect-response": "test_registration_and_refusals",
    "galileo-udp topic udp://{host}:3547/{path}?token={token}":
        "test_status_topic_streams_the_runtime_state",
    "galileo-udp cmd 0x02 id 0x01": "test_cmd_vel_text_turns_the_robot",
    "galileo-udp topic cmd_vel": "test_cmd_vel_text_turns_the_robot",
    "galileo-udp cmd 0x02 id 0x02": "test_long_messages_travel_as_binary_chunks",
    "galileo-udp cmd 0x02 id 0x00": "test_bad_datagrams_are_dropped_and_the_server_serves_on",
    "galileo-udp cmd 0x02 id 0x09": "test_ping_pong_both_ways",
    "galileo-udp cmd 0x02 id 0x0A": "test_ping_pong_both_ways",
    "galileo-udp cmd 0x02 id 0x08": "test_close_and_keep_alive_timeout",
}

TEXT, BINARY, CONTINUATION, CLOSE, PING, PONG = 0x01, 0x02, 0x00, 0x08, 0x09, 0x0A
CHUNK = 512
WAIT = 10.0  # [s wall] for a datagram that must come


class Client:
    """A UDP fast client as spec §4-§5 describe it."""

    def __init__(self, port: int, path: str, token: str = "") -> None:
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.bind(("127.0.0.1", 0))
        self.server = ("127.0.0.1", port)
        self.url = f"udp://127.0.0.1:{port}/{path}?token={token}"
        self.client_id = b""
        self.package_index = 0
        self.datagrams: list[bytes] = []  # every accepted datagram, in order
        self.partial = bytearray()

    def close(self) -> None:
        self.sock.close()

    def connect(self) -> dict[str, Any]:
        """Send the connection frame; the reply's JSON (from byte 6, A9)."""
        self.send_raw(b"\x01" + self.url.encode() + b"\x00")
        self.sock.settimeout(5.0)  # the example clients' wait
        reply, _ = self.sock.recvfrom(2048)
        body: dict[str, Any] = json.loads(reply[6:].decode())
        if body["status"]:
            self.client_id = bytes(body["client_id"])
            assert reply[:6] == b"\x02" + self.client_id + b"\x01"
        return body

    def send_raw(self, datagram: bytes) -> None:
        self.sock.sendto(datagram, self.server)

    def send(self, opcode: int, payload: bytes = b"") -> None:
        self.send_raw(b"\x02" + self.client_id + bytes((opcode,)) + payload)

    def send_text(self, text: str) -> None:
        self.send(TEXT, text.encode())

    def send_binary(self, data: bytes) -> None:
        """512-byte chunks, each with the next package_index (uint32 LE), as §4.5 (a pause
        after every 16, so a long message does not overrun the server's socket buffer)."""
        for n, start in enumerate(range(0, len(data), CHUNK), 1):
            self.send(BINARY, struct.pack("<I", self.package_index) + data[start:start + CHUNK])
            self.package_index += 1
            if n % 16 == 0:
                time.sleep(0.002)

    def sync(self) -> None:
        """PING, then read until the PONG: everything sent before has been handled."""
        self.send(PING)
        while self.frame()[0] != PONG:
            pass

    def frame(self, timeout: float = WAIT, *, answer_pings: bool = True) -> tuple[int, bytes]:
        """The next accepted data frame (opcode, payload after byte 5); PINGs are answered
        with PONG (and returned too)."""
        deadline = time.monotonic() + timeout
        while True:
            self.sock.settimeout(max(0.01, deadline - time.monotonic()))
            datagram, _ = self.sock.recvfrom(4096)
            assert len(datagram) <= 1024, len(datagram)
            if len(datagram) < 6 or datagram[0] != 2 or datagram[1:5] != self.client_id:
                continue
            self.datagrams.append(datagram)
            if datagram[5] == PING and answer_pings:
                self.send(PONG)
            return datagram[5], datagram[6:]

    def message(self, timeout: float = WAIT) -> dict[str, Any]:
        """The next JSON message: a TEXT frame, or BINARY chunks (index first) ended by a
        chunk shorter than 512 bytes."""
        deadline = time.monotonic() + timeout
        expected: int | None = None
        while True:
            opcode, payload = self.frame(max(0.01, deadline - time.monotonic()))
            if opcode == TEXT:
                decoded: dict[str, Any] = json.loads(payload.decode())
                return decoded
            if opcode == BINARY:
                (index,) = struct.unpack_from("<I", payload)
                assert expected is None or index == expected, (index, expected)
                expected = index + 1
                self.partial += payload[4:]
                if len(payload) - 4 < CHUNK:
                    text = bytes(self.partial)
                    self.partial.clear()
                    decoded = json.loads(text.decode())
                    return decoded

    def status_at(self, stamp: float, timeout: float = WAIT) -> dict[str, Any]:
        """The first message stamped at or after ``stamp`` (runtime seconds)."""
        deadline = time.monotonic() + timeout
        while True:
            message = self.message(max(0.01, deadline - time.monotonic()))
            s = message["header"]["stamp"]
            if s["secs"] + s["nsecs"] / 1e9 >= stamp - 1e-6:
                return message


class UdpServer:
    """The UDP fast listener on a loop thread of its own (``polynav run`` serves it on the
    Galileo servers' loop), with the timings a test chooses."""

    def __init__(self, ctx: Context, **options: float) -> None:
        self.loop = LoopThread()
        self.listener = UdpFastListener(ctx, "127.0.0.1", 0, **options)
        self.loop.run(self.listener.start())

    @property
    def port(self) -> int:
        return self.listener.port

    def stop(self) -> None:
        self.loop.run(self.listener.close())
        self.loop.close()


@pytest.fixture
def udp(galileo: Harness) -> Iterator[UdpServer]:
    server = UdpServer(galileo.server.ctx)
    try:
        yield server
    finally:
        server.stop()


@pytest.fixture
def clients() -> Iterator[list[Client]]:
    """Clients made in a test, closed at its end."""
    made: list[Client] = []
    yield made
    for client in made:
        client.close()


def _client(made: list[Client], port: int, path: str, token: str = "") -> Client:
    client = Client(port, path, token)
    made.append(client)
    return client



def test_every_udp_entry_has_a_test() -> None:
    assert sorted(set(spec.UDP) - set(COVERED)) == []
    assert sorted(set(COVERED) - set(spec.UDP)) == []


def test_registration_and_refusals(runtime: RobotRuntime, clients: list[Client]) -> None:
    with serving(runtime, galileo_config(require_token=True)) as g:
        server = UdpServer(g.server.ctx)
        try:
            port = server.port
            for path, token, why in (("galileo/status", "", "invalid token"),
                                     ("galileo/status", "0" * 32, "invalid token"),
                                     ("no/such/topic", "", "unknown topic /no/such/topic")):
                body = _client(clients, port, path, token).connect()
                assert body == {"status": False, "client_id": [], "description": why}
            token = g.ok("GET", "/token", params={"username": "admin", "password": "admin"})
            token = token["token"]
            assert _client(clients, port, "no/such", token).connect()["status"] is False
            ids = set()
            for path in ("galileo/status", "/galileo/status", "cmd_vel", "/cmd_vel"):  # A27
                body = _client(clients, port, path, token).connect()
                assert body["status"] is True, body
                assert len(body["client_id"]) == 4
                assert all(isinstance(b, int) and 0 <= b <= 255 for b in body["client_id"])
                ids.add(bytes(body["client_id"]))
            assert len(ids) == 4 and server.listener.clients == 4
            # Connection frames that are not §4.4's: the same failure reply, with the reason.
            raw = _client(clients, port, "galileo/status", token)
            raw.sock.settimeout(5.0)
            for frame, why in ((b"\x01udp://127.0.0.1/galileo/status", "ends with 0x00"),
                               (b"\x01http://h/galileo/status\x00", "udp://"),
                               (b"\x01udp://127.0.0.1:1/\x00", "names no topic"),
                               (b"\x01\xff\xfe\x00", "UTF-8"),
                               (b"\x01udp://h/x?token=" + b"a" * 1100 + b"\x00", "at most")):
                raw.send_raw(frame)
                reply, _ = raw.sock.recvfrom(2048)
                assert reply[:6] == b"\x02\x00\x00\x00\x00\x01"
                body = json.loads(reply[6:])
                assert body["status"] is False and why in body["description"], (frame, body)
        finally:
            server.stop()


def test_status_topic_streams_the_runtime_state(galileo: Harness, udp: UdpServer,
                                                clients: list[Client]) -> None:
    client = _client(clients, udp.port, "galileo/status")
    assert client.connect()["status"] is True
    first = client.message()
    assert list(first) == list(FIELDS)
    galileo.ok("GET", "/navigation/start", params={"map": "floor1", "start_index": 1})
    for _ in range(3):
        galileo.runtime.advance(0.35)
        expected = galileo_status(galileo.server.ctx)
        stamp = expected["header"]["stamp"]
        message = client.status_at(stamp["secs"] + stamp["nsecs"] / 1e9)
        assert message["header"]["seq"] > first["header"]["seq"]
        assert message["header"]["stamp"] == stamp
        for name in FIELDS:
            if name != "header":
                assert message[name] == pytest.approx(expected[name], abs=1e-6), name
    assert message["navStatus"] == 1
    pose = galileo.runtime.status().pose
    assert message["currentPosX"] == pytest.approx(pose.x, abs=1e-3)
    assert message["currentPosY"] == pytest.approx(pose.y, abs=1e-3)
    # At the topic's rate on the runtime's clock, 10 Hz: 4 messages in 10 steps of 0.04 s
    # (two 0.02 s physics steps each).
    galileo.runtime.advance(0.1)
    with pytest.raises(TimeoutError):  # what is due now (a catch-up after a jump) is sent
        while True:
            client.message(timeout=0.3)
    got = []
    for _ in range(10):
        galileo.runtime.advance(0.04)
        try:
            client.message(timeout=0.3)
            got.append(True)
        except TimeoutError:
            got.append(False)
    assert got.count(True) == 4, got


def test_cmd_vel_text_turns_the_robot(galileo: Harness, udp: UdpServer,
                                      clients: list[Client],
                                      monkeypatch: pytest.MonkeyPatch) -> None:
    applied = threading.Semaphore(0)
    teleop = galileo.runtime.teleop

    def counted(linear: float, angular: float) -> None:
        teleop(linear, angular)
        applied.release()

    monkeypatch.setattr(galileo.runtime, "teleop", counted)
    client = _client(clients, udp.port, "cmd_vel")  # the examples' path, no leading slash
    assert client.connect()["status"] is True
    before = galileo.runtime.simulation.true_pose
    twist = {"linear": {"x": 0.0, "y": 0.0, "z": 0.0}, "angular": {"x": 0.0, "y": 0.0, "z": 0.5}}
    for n in range(10):
        if n % 2:  # as Send(byte[]): BINARY chunks, here padded past one chunk
            client.send_binary(json.dumps(twist).encode() + b" " * 600)
        else:
            client.send_text(json.dumps(twist))
        assert applied.acquire(timeout=WAIT)
        galileo.runtime.advance(0.2)
    after = galileo.runtime.simulation.true_pose
    turned = math.remainder(after.theta - before.theta, math.tau)
    assert turned > 0.3
    assert math.hypot(after.x - before.x, after.y - before.y) < 0.05
    # A message that is no Twist, or no JSON, gets the WebSocket's error object.
    client.send_text('{"linear": {"x": "fast"}, "angular": {}}')
    error = client.message()
    assert error["status"] == "error" and "linear.x" in error["description"]
    client.send_text("not json")
    assert client.message()["status"] == "error"
    client.send_binary(b"\xff\xfe")
    assert client.message()["status"] == "error"


def test_galileo_cmds_runs_a_native_command(galileo: Harness, udp: UdpServer,
                                            clients: list[Client]) -> None:
    client = _client(clients, udp.port, "galileo/cmds")
    assert client.connect()["status"] is True
    client.send_text(json.dumps({"length": 2, "data": [0x6D, 0x05, 0x01]}))
    error = client.message()
    assert error["status"] == "error" and "does not count" in error["description"]
    assert galileo.runtime.status().mode != "navigating"
    client.send_text(json.dumps(encode_native_cmds(c.start_navigation())))
    assert galileo.advance_until(lambda: galileo.runtime.status().mode == "navigating", 20.0,
                                 step=0.2, pause=0.01)


def test_long_messages_travel_as_binary_chunks(galileo: Harness, udp: UdpServer,
                                               clients: list[Client]) -> None:
    galileo.ok("GET", "/navigation/start", params={"map": "floor1", "start_index": 1})
    galileo.runtime.advance(2.0)
    scan_client = _client(clients, udp.port, "scan")
    assert scan_client.connect()["status"] is True
    for _ in range(2):
        scan = scan_client.message()
        n = len(scan["ranges"])
        assert n > 100
        assert math.isclose(scan["angle_max"],
                            scan["angle_min"] + (n - 1) * scan["angle_increment"])
        galileo.runtime.advance(0.1)
    binary = [d for d in scan_client.datagrams if d[5] == BINARY]
    assert len(binary) >= 2
    indices = [struct.unpack_from("<I", d, 6)[0] for d in binary]
    assert indices == list(range(len(binary))), "one counter from 0, +1 per BINARY frame"
    sizes = [len(d) - 10 for d in binary]
    assert max(sizes) == CHUNK and sizes.count(CHUNK) == len(sizes) - 2, "two messages"
    map_client = _client(clients, udp.port, "map")
    map_client.sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4 * 1024 * 1024)
    assert map_client.connect()["status"] is True
    grid = map_client.message(timeout=15.0)
    info = grid["info"]
    assert (info["width"], info["height"], info["resolution"]) == (820, 500, 0.05)
    assert len(grid["data"]) == 820 * 500 and set(grid["data"]) <= {-1, 0, 100}
    assert len(map_client.datagrams) > 2000


def test_ping_pong_both_ways(udp: UdpServer, clients: list[Client]) -> None:
    client = _client(clients, udp.port, "cmd_vel")  # a topic that sends nothing: only pings
    assert client.connect()["status"] is True
    client.send(PING)
    opcodes = []
    start = time.monotonic()
    while time.monotonic() - start < 1.0:
        opcodes.append(client.frame()[0])
    assert PONG in opcodes, "a client's ping is answered"
    assert 5 <= opcodes.count(PING) <= 15, "the robot pings at about 10 Hz"
    assert set(opcodes) <= {PING, PONG}
    assert client.datagrams[-1] in (b"\x02" + client.client_id + b"\x09",
                                    b"\x02" + client.client_id + b"\x0a")


def test_close_and_keep_alive_timeout(galileo: Harness, clients: list[Client]) -> None:
    server = UdpServer(galileo.server.ctx, client_timeout=0.6, ping_interval=0.05)
    try:
        closing = _client(clients, server.port, "galileo/status")
        silent = _client(clients, server.port, "galileo/status")
        alive = _client(clients, server.port, "galileo/status")
        for client in (closing, silent, alive):
            assert client.connect()["status"] is True
        assert server.listener.clients == 3
        # CLOSE: dropped, no reply; a later frame with the forgotten id is told CLOSE.
        closing.send(CLOSE)
        deadline = time.monotonic() + WAIT
        while server.listener.clients != 2:
            assert time.monotonic() < deadline
            time.sleep(0.01)
        closing.send(PING)
        while (opcode := closing.frame(answer_pings=False)[0]) != CLOSE:
            assert opcode in (TEXT, PING), opcode  # sent before the close took effect
        # The silent one is dropped with a CLOSE after the timeout; the one answering pings is
        # not.
        silent_opcodes = []
        start = time.monotonic()
        while (opcode := silent.frame(answer_pings=False)[0]) != CLOSE:
            silent_opcodes.append(opcode)
            alive.frame()  # keeps answering pings
        assert 0.4 < time.monotonic() - start < 5.0
        assert PING in silent_opcodes
        for _ in range(40):  # two timeouts' worth of pings
            opcode, _ = alive.frame()
            assert opcode != CLOSE
        assert server.listener.clients == 1
    finally:
        server.stop()
    # The server closing tells the remaining client.
    while (opcode := alive.frame(answer_pings=False)[0]) != CLOSE:
        pass


def test_bad_datagrams_are_dropped_and_the_server_serves_on(
        galileo: Harness, udp: UdpServer, clients: list[Client],
        caplog: pytest.LogCaptureFixture) -> None:
    client = _client(clients, udp.port, "cmd_vel")
    assert client.connect()["status"] is True
    rng = random.Random(35)
    cid = client.client_id
    bad = [b"", b"\x02", b"\x02" + cid, b"\x02" + cid[:2], b"\x02" + cid + b"\x02\x00",
           b"\x02" + cid + b"\x02" + b"\x00" * 3, b"\x02" + cid + b"\x7f" + b"junk",
           b"\x02" + cid + b"\x01" + b"{" * 2000, b"\x03" + cid + b"\x09", b"\xff" * 50,
           b"\x02" + cid + b"\x00" + b"continued"]
    bad += [garbage(rng) for _ in range(200)]
    for n, datagram in enumerate(bad):
        client.send_raw(datagram)
        if n % 32 == 0:
            client.sync()
    client.sync()
    # A client of another address using this id is ignored (no reply, no effect).
    other = _client(clients, udp.port, "cmd_vel")
    other.client_id = cid
    other.send(PING)
    # An inbound BINARY message past 64 KiB is refused once with an error.
    client.send_binary(b"[" * (65 * 1024))
    error = client.message()
    assert error["status"] == "error" and "at most" in error["description"]
    client.sync()
    other.sock.settimeout(0.3)
    with pytest.raises(TimeoutError):
        other.sock.recvfrom(2048)
    assert udp.listener.clients == 1
    assert tracebacks(caplog) == []
    counts = diagnostics(galileo.server.ctx).snapshot()  # each kind of bad input counted
    for name in ("udp.empty_datagram", "udp.unknown_frame_type", "udp.malformed_frame",
                 "udp.foreign_address", "udp.message_too_long"):
        assert counts.get(name, 0) >= 1, (name, counts)
    fresh = _client(clients, udp.port, "galileo/status")
    assert fresh.connect()["status"] is True
    assert "navStatus" in fresh.message()


def test_a_client_flooding_a_slow_topic_is_told_busy(galileo: Harness, udp: UdpServer,
                                                     clients: list[Client],
                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    release = threading.Event()
    applied: list[float] = []

    def slow(linear: float, angular: float) -> None:
        release.wait(WAIT)
        applied.append(angular)

    monkeypatch.setattr(galileo.runtime, "teleop", slow)
    client = _client(clients, udp.port, "cmd_vel")
    assert client.connect()["status"] is True
    try:
        for n in range(80):
            twist = {"linear": {"x": 0.0}, "angular": {"z": n / 100}}
            client.send_text(json.dumps(twist))
            if n % 16 == 0:
                client.sync()
        client.sync()
        replies = [json.loads(d[6:]) for d in client.datagrams if d[5] == TEXT]
        assert len(replies) == 80 - 65
        assert all(r["status"] == "error" and "busy" in r["description"] for r in replies)
    finally:
        release.set()
    deadline = time.monotonic() + WAIT
    while len(applied) < 65 and time.monotonic() < deadline:
        time.sleep(0.01)
    time.sleep(0.1)
    # One being published and 64 waiting; the rest were refused. Order is kept.
    assert len(applied) == 65 and applied == sorted(applied) and applied[0] == 0.0
