"""The Yunji TCP and HTTP listeners under fuzzing: commands from ``yunji-api.endpoints.json``
with wrong and random parameters, raw garbage, split writes, abrupt closes, many connections.

Bounded in count and wall time and seeded, so a failure replays. The server must log no
traceback, still answer ``robot_status`` and not grow the process's memory past a bound.
"""

from __future__ import annotations

import json
import logging
import random
from collections.abc import Iterator

import pytest

from polynav.protocols.yunji import YunjiConfig
from polynav.runtime.robot_runtime import RobotRuntime
from tests.conftest import DATA
from tests.helpers import wire_fuzz
from tests.protocols.yunji.conftest import Harness, serving

ENTRIES = json.loads((DATA / "spec" / "yunji-api.endpoints.json").read_text(encoding="utf-8"))
COMMANDS = [e for e in ENTRIES if e["method"] == "cmd"]
PATHS = sorted({e["path"].split("?", 1)[0] for e in COMMANDS})
NAMES = sorted(
    set(wire_fuzz.query_names(e["title"] for e in COMMANDS))
    | {"marker", "markers", "location", "count", "flag", "uuid", "topic", "frequency", "name",
       "type", "num", "floor", "x", "y", "theta", "reboot", "delay", "map_name", "speed",
       "angular_speed", "linear_speed", "distance_tolerance", "theta_tolerance",
       "max_continuous_retries", "yaw_goal_reverse_allowed", "start", "goal", "points",
       "luminance", "color", "ssid", "password", "angle_offset", "switch"}
)
MEMORY_BOUND = 64 * 1024 * 1024  # [bytes] growth allowed over a whole run


def _command(rng: random.Random) -> str:
    path = rng.choice(PATHS)
    if path == "/api/request_data" and rng.random() < 0.7:
        path += f"?topic={rng.choice(['robot_status', 'human_detection', 'robot_velocity'])}"
    return wire_fuzz.random_query(path, NAMES, rng)


def _frame(rng: random.Random) -> bytes:
    text = _command(rng)
    ending = rng.choice(["\n", "\n", "\r\n", ""])
    return text.encode("utf-8", "surrogatepass") + ending.encode()


@pytest.fixture
def web(runtime: RobotRuntime) -> Iterator[Harness]:
    with serving(runtime, YunjiConfig(port=0, http_port=0, queue_size=64)) as h:
        yield h


def _still_answers(h: Harness) -> None:
    reply = h.client().request("/api/robot_status")
    assert reply["type"] == "response" and reply["command"] == "/api/robot_status"
    assert reply["status"] in ("OK", "REQUEST_DENIED"), reply  # denied while powered off


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_the_tcp_listener_survives_fuzzing(
    web: Harness, caplog: pytest.LogCaptureFixture, seed: int
) -> None:
    caplog.set_level(logging.WARNING, logger="polynav")
    before = wire_fuzz.rss_bytes()
    ticks = iter(range(10**9))

    def advance() -> None:
        if next(ticks) % 25 == 0:
            web.runtime.advance(0.2)

    report = wire_fuzz.fuzz_stream(
        web.server.port, _frame, seed=seed, frames=3000, connections=20, time_limit=40.0,
        between=advance,
    )
    assert report.frames > 200 and report.connections > 5
    assert wire_fuzz.tracebacks(caplog) == []
    _still_answers(web)
    assert wire_fuzz.rss_bytes() - before < MEMORY_BOUND


def test_the_http_listener_survives_fuzzing(web: Harness, caplog: pytest.LogCaptureFixture) -> None:
    caplog.set_level(logging.WARNING, logger="polynav")
    port = web.server.http_port
    assert port is not None
    before = wire_fuzz.rss_bytes()

    def target(rng: random.Random) -> str:
        text = quote_target(_command(rng))
        return text if rng.random() < 0.95 else "/" + "x" * rng.randrange(1, 20000)

    report = wire_fuzz.fuzz_http(port, target, seed=3, requests=800, time_limit=40.0)
    assert report.frames > 200
    assert set(report.http_status) <= {200, 400, 404, 405, 413, 414, 431}, report.http_status
    assert wire_fuzz.tracebacks(caplog) == []
    _still_answers(web)
    assert wire_fuzz.rss_bytes() - before < MEMORY_BOUND


def quote_target(target: str) -> str:
    """What an HTTP client can put on a request line: non-ASCII and spaces escaped."""
    return "".join(c if 33 <= ord(c) < 127 else f"%{ord(c) & 0xFF:02X}" for c in target)
