"""The rosapi services clients call first, answered by the server from the graph."""

from __future__ import annotations

from tests.protocols.rosbridge.conftest import Client, SampleGraph


def test_topics_lists_published_and_taken_topics_with_types(client: Client) -> None:
    values = client.call("/rosapi/topics", {})["values"]
    pairs = dict(zip(values["topics"], values["types"], strict=True))
    assert pairs == {"/command": "std_msgs/String", "/counter": "std_msgs/Int16",
                     "/state": "std_msgs/String"}


def test_services_lists_the_graphs_and_rosapis(client: Client) -> None:
    services = client.call("/rosapi/services")["values"]["services"]
    assert {"/add", "/fail", "/slow", "/rosapi/topics", "/rosapi/get_time"} <= set(services)


def test_topic_and_service_type(client: Client) -> None:
    assert client.call("/rosapi/topic_type", {"topic": "/counter"})["values"] == {
        "type": "std_msgs/Int16"}
    assert client.call("/rosapi/topic_type", {"topic": "/nope"})["values"] == {"type": ""}
    assert client.call("/rosapi/service_type", {"service": "/fail"})["values"] == {
        "type": "std_srvs/Trigger"}
    reply = client.call("/rosapi/topic_type", {})
    assert reply["result"] is False and "'topic'" in reply["values"]


def test_get_time_is_the_clock_given(sample: SampleGraph, client: Client) -> None:
    assert client.call("/rosapi/get_time")["values"] == {"time": {"secs": 12,
                                                                  "nsecs": 500000000}}
    sample.clock.advance(1.25)
    assert client.call("/rosapi/get_time")["values"]["time"] == {"secs": 13,
                                                                 "nsecs": 750000000}


def test_nodes(client: Client) -> None:
    assert "/rosbridge_websocket" in client.call("/rosapi/nodes")["values"]["nodes"]
