"""The rosapi services rosbridge clients call first: what topics and services there are, their
types, and the robot's time.

roslibpy and roslibjs ask ``/rosapi/topics`` before anything else and wait for the answer, so
these are answered by the server itself from the graph, never from the runtime's loop.
"""

from __future__ import annotations

from polynav.clock import Clock
from polynav.protocols.ros_graph import Graph, Message, RosError, Service

NODES = ("/rosbridge_websocket", "/rosapi", "/polynav")


def stamp(seconds: float) -> dict[str, int]:
    """A ``time`` value: whole seconds and nanoseconds (never negative)."""
    seconds = max(0.0, seconds)
    secs = int(seconds)
    return {"secs": secs, "nsecs": min(999_999_999, int(round((seconds - secs) * 1e9)))}


def rosapi_services(graph: Graph, clock: Clock) -> dict[str, Service]:
    """The rosapi services over ``graph``, by name."""

    def topic_names() -> list[tuple[str, str]]:
        seen: dict[str, str] = {t.name: t.type for t in graph.topics()}
        for sub in graph.subscriptions():
            seen.setdefault(sub.name, sub.type)
        return sorted(seen.items())

    def service_types() -> dict[str, str]:
        types = {s.name: s.type for s in graph.services()}
        types.update({name: kind for name, kind in _ROSAPI_TYPES.items()})
        return dict(sorted(types.items()))

    def topics(args: Message) -> Message:
        pairs = topic_names()
        return {"topics": [n for n, _ in pairs], "types": [t for _, t in pairs]}

    def services(args: Message) -> Message:
        return {"services": list(service_types())}

    def topic_type(args: Message) -> Message:
        name = _text(args, "topic")
        return {"type": dict(topic_names()).get(name, "")}

    def service_type(args: Message) -> Message:
        name = _text(args, "service")
        return {"type": service_types().get(name, "")}

    def nodes(args: Message) -> Message:
        return {"nodes": list(NODES)}

    def get_time(args: Message) -> Message:
        return {"time": stamp(clock.now())}

    calls = {
        "/rosapi/topics": topics, "/rosapi/services": services,
        "/rosapi/topic_type": topic_type, "/rosapi/service_type": service_type,
        "/rosapi/nodes": nodes, "/rosapi/get_time": get_time,
    }
    return {name: Service(name, _ROSAPI_TYPES[name], call) for name, call in calls.items()}


_ROSAPI_TYPES = {
    "/rosapi/topics": "rosapi/Topics",
    "/rosapi/services": "rosapi/Services",
    "/rosapi/topic_type": "rosapi/TopicType",
    "/rosapi/service_type": "rosapi/ServiceType",
    "/rosapi/nodes": "rosapi/Nodes",
    "/rosapi/get_time": "rosapi/GetTime",
}


def _text(args: Message, key: str) -> str:
    value = args.get(key)
    if not isinstance(value, str):
        raise RosError(f"'{key}' must be a string")
    return value
