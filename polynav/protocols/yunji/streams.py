"""``/api/request_data`` (§3.9): callback streams, their topics, rates and results.

A topic is a default rate and a function that builds one callback's ``results``. The server keeps
one stream per (connection, topic) and calls :func:`stream_results` each period.
"""

from __future__ import annotations

from collections.abc import Callable

from polynav.errors import InvalidRequest
from polynav.protocols.yunji.context import Context, Params, optional_float, required
from polynav.protocols.yunji.messages import Reply, StreamRequest
from polynav.protocols.yunji.robot import robot_status

STREAM_MAX_RATE = 20.0


def _robot_status(ctx: Context) -> object:
    return robot_status(ctx, {}).results


def _robot_velocity(ctx: Context) -> object:
    s = ctx.runtime.status()
    return {"angular": float(s.angular), "linear": float(s.linear)}


def _human_detection(ctx: Context) -> object:
    """§3.9.2, §A-R3: ``"legtrack <id>"`` -> position and velocity in the robot frame [m,
    m/s]; ``{}`` when nobody is seen. From the robot's leg tracker."""
    runtime = ctx.runtime
    people = runtime.run_between_ticks(runtime.robot.read_people)
    return {
        f"legtrack {p.track_id}": {
            "position": {"x": p.x, "y": p.y},
            "velocity": {"x": p.vx, "y": p.vy},
        }
        for p in people
    }


# topic -> (default rate [Hz], results builder) (§3.9, §A-R2).
TOPICS: dict[str, tuple[float, Callable[[Context], object]]] = {
    "robot_status": (2.0, _robot_status),
    "human_detection": (1.0, _human_detection),
    "robot_velocity": (1.0, _robot_velocity),
}


def request_data(ctx: Context, params: Params) -> Reply:
    """§3.9: start (or with the deprecated ``switch=off``, stop) a callback stream of
    ``topic`` on this connection; a repeated request replaces the rate (§A-R1)."""
    topic = required(params, "topic")
    if topic not in TOPICS:
        raise InvalidRequest("topic", f"unknown topic {topic!r}")
    switch = params.get("switch", "on")
    if switch not in ("on", "off"):
        raise InvalidRequest("switch", f"must be on or off, got {switch!r}")
    frequency = optional_float(params, "frequency", TOPICS[topic][0])
    assert frequency is not None
    if not 0.0 < frequency <= STREAM_MAX_RATE:
        raise InvalidRequest(
            "frequency", f"must be in (0, {STREAM_MAX_RATE:g}] Hz, got {frequency:g}"
        )
    return Reply(stream=StreamRequest(topic, frequency, switch == "on"))


# Topics read from the robot itself (its sensors), silent while it is powered off.
NEED_POWER = frozenset({"human_detection"})


def stream_results(ctx: Context, topic: str) -> object:
    """The ``results`` of one callback of ``topic``."""
    return TOPICS[topic][1](ctx)


def still_current(ctx: Context, topic: str) -> bool:
    """Whether results computed a moment ago may still be sent: a sensor reading taken just
    before a power cut is not sent after it (the robot is off by then)."""
    return topic not in NEED_POWER or ctx.runtime.powered


HANDLERS = {"/api/request_data": request_data}
