"""``/galileo/status`` on a ROS graph: the Galileo status message at 10 Hz of the runtime's
clock, from the same encoder and context as the WebSocket and HTTP."""

from __future__ import annotations

from typing import Any

from polynav.protocols.galileo.ros_topics import STATUS, add_galileo_topics
from polynav.protocols.ros_graph import Graph
from tests.protocols.galileo.conftest import Harness


def test_galileo_status_is_published_at_ten_hertz_of_runtime_time(galileo: Harness) -> None:
    graph = Graph()
    got: list[dict[str, Any]] = []
    graph.add_sink(lambda name, message: got.append(message) if name == STATUS.name else None)
    stop = add_galileo_topics(graph, galileo.server.ctx)
    assert graph.topic("/galileo/status") == STATUS
    assert STATUS.type == "galileo_msg/GalileoStatus"
    start = galileo.runtime.now()
    galileo.runtime.advance(5.0)
    assert 49 <= len(got) <= 51  # 10 Hz over 5 s of simulated time
    stamps = [m["header"]["stamp"]["secs"] + m["header"]["stamp"]["nsecs"] * 1e-9 for m in got]
    assert stamps == sorted(stamps) and stamps[0] >= start
    seqs = [m["header"]["seq"] for m in got]
    assert seqs == sorted(set(seqs))  # one sequence, shared with the WebSocket's
    last = got[-1]
    assert last["header"]["frame_id"] == "map"
    http = galileo.ok("GET", "/system/galileo_status")  # one encoder: the same fields
    assert list(last) == list(http)
    assert last["power"] == http["power"] and last["navStatus"] == http["navStatus"]
    stop()
    count = len(got)
    galileo.runtime.advance(1.0)
    assert len(got) == count
