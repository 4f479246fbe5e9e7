"""Byte-level fuzzing of a dialect's listeners, shared by every dialect's fuzz test.

A dialect's test builds its command frames from the dialect's endpoint list (paths, parameter
names it documents) and hands them to :func:`fuzz_stream` (a TCP command socket) or
:func:`fuzz_http` (an HTTP listener). They mix them with wrong and random parameter values, raw
garbage, writes split at random points, abrupt closes and many connections, bounded in count and
in time, seeded, and read whatever the server answers so it is never blocked on a full socket.
The test then checks what matters: no traceback was logged (:func:`tracebacks`), the server still
answers a plain request, and the process's memory did not grow beyond a bound (:func:`rss_bytes`).
"""

from __future__ import annotations

import http.client
import logging
import random
import re
import socket
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from urllib.parse import quote

import pytest

# Values that break parsers: empty, huge, non-finite, wrong type, separators, non-ASCII, escapes.
NASTY_VALUES: tuple[str, ...] = (
    "", "0", "-1", "1", "true", "false", "yes", "nan", "inf", "-inf", "1e309", "-1e309",
    "9223372036854775808", "-9223372036854775809", "99999999999999999999999999", "0x10",
    "1.5", "-0.0", "1,2", "1,2,3", "1,2,3,4", ",,,", "a,b,c", "null", "[]", "{}", "%", "%zz",
    "%00", "\u00e9\u4e2d", "\x00\x01\x7f", "'\";--", "../../etc/passwd", "a" * 5000,
    "lobby", "kitchen", "charger", "floor1", "floor2", "1,1,0", "5.5,12.5,0.0",
)


def nasty_value(rng: random.Random) -> str:
    """A parameter value: usually one of :data:`NASTY_VALUES`, sometimes random bytes as text."""
    if rng.random() < 0.8:
        return rng.choice(NASTY_VALUES)
    return "".join(chr(rng.randrange(1, 0x2FF)) for _ in range(rng.randrange(0, 40)))


def query_names(titles: Iterable[str]) -> list[str]:
    """Parameter names a spec entry's title mentions (``name=``), for building queries."""
    names: set[str] = set()
    for title in titles:
        names.update(re.findall(r"([A-Za-z_][A-Za-z0-9_]*)=", title))
    return sorted(names)


def random_query(path: str, names: Sequence[str], rng: random.Random) -> str:
    """``path`` with 0..4 parameters drawn from ``names`` (and a stray one), values nasty,
    percent-encoded or raw at random."""
    params = []
    for _ in range(rng.randrange(0, 5)):
        name = rng.choice(names) if names and rng.random() < 0.85 else nasty_value(rng)[:12]
        value = nasty_value(rng)
        if rng.random() < 0.6:
            value = quote(value, safe=",")
        params.append(f"{name}={value}")
    if not params:
        return path
    joiner = "?" if "?" not in path else "&"
    return path + joiner + "&".join(params)


def garbage(rng: random.Random) -> bytes:
    """Raw bytes that are not a command: random, control characters, JSON, HTTP, half frames."""
    kind = rng.randrange(6)
    if kind == 0:
        return rng.randbytes(rng.randrange(1, 2000))
    if kind == 1:
        return b"\r\n" * rng.randrange(1, 50)
    if kind == 2:
        return b'{"command": "/api/move", "marker": [1, 2]}\n'
    if kind == 3:
        return b"GET /api/robot_status HTTP/1.1\r\nHost: x\r\n\r\n"
    if kind == 4:
        return b"/api/" + bytes(rng.randrange(32, 127) for _ in range(rng.randrange(0, 300)))
    return b"\xff\xfe" + b"/api/robot_status".replace(b"/", b"\x00/")


def split_writes(data: bytes, rng: random.Random) -> list[bytes]:
    """``data`` cut at random points (whole, a few pieces, or byte by byte)."""
    if len(data) < 2 or rng.random() < 0.5:
        return [data]
    if rng.random() < 0.1 and len(data) < 200:
        return [data[i : i + 1] for i in range(len(data))]
    cuts = sorted(rng.sample(range(1, len(data)), min(len(data) - 1, rng.randrange(1, 5))))
    return [data[a:b] for a, b in zip([0, *cuts], [*cuts, len(data)], strict=True)]


@dataclass
class FuzzReport:
    """What a fuzz run sent and what came back."""

    frames: int = 0
    connections: int = 0
    abrupt_closes: int = 0
    bytes_received: int = 0
    http_status: dict[int, int] = field(default_factory=dict)


def _drain(sock: socket.socket) -> int:
    """Read what is waiting without blocking; the byte count (0 also when the peer closed)."""
    got = 0
    sock.setblocking(False)
    try:
        while True:
            chunk = sock.recv(65536)
            if not chunk:
                break
            got += len(chunk)
    except (BlockingIOError, ConnectionError, OSError):
        pass
    finally:
        sock.setblocking(True)
    return got


def fuzz_stream(
    port: int,
    make_frame: Callable[[random.Random], bytes],
    *,
    seed: int,
    frames: int,
    connections: int,
    time_limit: float,
    between: Callable[[], None] | None = None,
) -> FuzzReport:
    """Send ``frames`` frames (``make_frame`` or :func:`garbage`) over ``connections``
    connections to ``127.0.0.1:port``, split at random, some connections closed abruptly
    mid-frame. Stops early after ``time_limit`` [s wall]; ``between`` runs between frames
    (e.g. to advance simulated time)."""
    rng = random.Random(seed)
    report = FuzzReport()
    deadline = time.monotonic() + time_limit
    socks: list[socket.socket] = []
    try:
        for _ in range(frames):
            if time.monotonic() > deadline:
                break
            if len(socks) < connections and (not socks or rng.random() < 0.1):
                socks.append(socket.create_connection(("127.0.0.1", port), timeout=5.0))
                report.connections += 1
            sock = rng.choice(socks)
            frame = garbage(rng) if rng.random() < 0.15 else make_frame(rng)
            try:
                pieces = split_writes(frame, rng)
                if rng.random() < 0.03:  # abrupt close in the middle of a frame
                    sock.sendall(pieces[0][: max(1, len(pieces[0]) // 2)])
                    sock.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, b"\x01\0\0\0\0\0\0\0")
                    sock.close()
                    socks.remove(sock)
                    report.abrupt_closes += 1
                    continue
                for piece in pieces:
                    sock.sendall(piece)
                report.frames += 1
            except OSError:  # the server closed this one (e.g. an oversized frame): fine
                socks.remove(sock)
                sock.close()
                continue
            for s in socks:
                report.bytes_received += _drain(s)
            if between is not None:
                between()
    finally:
        for s in socks:
            s.close()
    return report


def fuzz_http(
    port: int,
    make_target: Callable[[random.Random], str],
    *,
    seed: int,
    requests: int,
    time_limit: float,
    methods: Sequence[str] = ("GET",),
) -> FuzzReport:
    """Send ``requests`` HTTP requests (targets from ``make_target``, some with an odd method
    or a body) over kept-alive connections to ``127.0.0.1:port``; counts the status codes."""
    rng = random.Random(seed)
    report = FuzzReport()
    deadline = time.monotonic() + time_limit
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=10.0)
    try:
        for _ in range(requests):
            if time.monotonic() > deadline:
                break
            target = make_target(rng)
            method = rng.choice(methods) if rng.random() < 0.9 else rng.choice(
                ("POST", "PUT", "DELETE", "PATCH", "OPTIONS"))
            body = rng.randbytes(rng.randrange(0, 500)) if method != "GET" else None
            try:
                conn.request(method, target, body=body)
                reply = conn.getresponse()
                reply.read()
                report.http_status[reply.status] = report.http_status.get(reply.status, 0) + 1
                report.frames += 1
            except (http.client.HTTPException, OSError, UnicodeError):
                conn.close()  # a target http.client cannot send, or the server hung up
                conn = http.client.HTTPConnection("127.0.0.1", port, timeout=10.0)
                report.connections += 1
    finally:
        conn.close()
    return report


def tracebacks(caplog: pytest.LogCaptureFixture) -> list[str]:
    """Every log record with a traceback, or at ERROR or above, as text."""
    return [
        f"{r.name}: {r.getMessage()}"
        for r in caplog.records
        if r.exc_info is not None or r.levelno >= logging.ERROR
    ]


def rss_bytes() -> int:
    """This process's resident set size [bytes], from /proc (Linux)."""
    with open("/proc/self/statm") as statm:
        pages = int(statm.read().split()[1])
    import resource

    return pages * resource.getpagesize()
