"""roslibpy, a real rosbridge client from PyPI, drives the server: it connects, lists topics
(its first call), subscribes, publishes and calls services.

roslibpy runs Twisted's reactor on a thread of its own, once per process (it cannot restart):
the tests share one reactor and each opens and closes its own connection.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Iterator
from typing import Any

import pytest

from polynav.protocols.rosbridge import RosbridgeThread
from tests.protocols.rosbridge.conftest import SampleGraph

roslibpy = pytest.importorskip("roslibpy")

TIMEOUT = 10.0


@pytest.fixture
def ros(server: RosbridgeThread) -> Iterator[Any]:
    client = roslibpy.Ros(host="127.0.0.1", port=server.port)
    client.run(timeout=TIMEOUT)
    try:
        yield client
    finally:
        client.close()


def test_roslibpy_lists_topics_and_services(ros: Any) -> None:
    assert set(ros.get_topics()) == {"/command", "/counter", "/state"}
    assert ros.get_topic_type("/counter") == "std_msgs/Int16"
    assert "/add" in ros.get_services()
    assert ros.get_time()["secs"] == 12


def test_roslibpy_subscribes_and_publishes(sample: SampleGraph, ros: Any) -> None:
    got: list[int] = []
    arrived = threading.Event()

    def on_message(msg: dict[str, Any]) -> None:
        got.append(msg["data"])
        if len(got) == 3:
            arrived.set()

    counter = roslibpy.Topic(ros, "/counter", "std_msgs/Int16", queue_length=10)
    counter.subscribe(on_message)
    ros.get_time()  # the subscribe op is handled before this call's answer
    for i in range(3):
        sample.graph.publish("/counter", {"data": i})
    assert arrived.wait(TIMEOUT) and got == [0, 1, 2]
    counter.unsubscribe()
    command = roslibpy.Topic(ros, "/command", "std_msgs/String")
    command.publish(roslibpy.Message({"data": "go"}))
    deadline = time.monotonic() + TIMEOUT
    while not sample.commands and time.monotonic() < deadline:
        time.sleep(0.01)
    assert sample.commands == [{"data": "go"}]
    command.unadvertise()


def test_roslibpy_calls_a_service_and_sees_a_failure(ros: Any) -> None:
    add = roslibpy.Service(ros, "/add", "test_srvs/Add")
    assert add.call(roslibpy.ServiceRequest({"a": 20, "b": 22}), timeout=TIMEOUT) == {"sum": 42}
    fail = roslibpy.Service(ros, "/fail", "std_srvs/Trigger")
    with pytest.raises(Exception, match="always fails"):
        fail.call(roslibpy.ServiceRequest({}), timeout=TIMEOUT)
