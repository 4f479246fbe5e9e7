"""The rosbridge v2 ops over a real WebSocket: subscribe and publish with their options,
service calls with id correlation, advertise, unsubscribe, set_level."""

from __future__ import annotations

import time

from tests.protocols.rosbridge.conftest import Client, SampleGraph


def test_subscribe_gets_published_messages_in_order(sample: SampleGraph,
                                                    client: Client) -> None:
    client.send({"op": "subscribe", "id": "s1", "topic": "/counter", "type": "std_msgs/Int16",
                 "queue_length": 10})
    client.call("/rosapi/get_time")  # the subscription is in once a later op has answered
    for i in range(5):
        sample.graph.publish("/counter", {"data": i})
    got = [client.recv_op("publish", topic="/counter")["msg"]["data"] for _ in range(5)]
    assert got == [0, 1, 2, 3, 4]


def test_a_latched_topic_sends_its_last_message_on_subscribe(sample: SampleGraph,
                                                             client: Client) -> None:
    sample.graph.publish("/state", {"data": "ready"})
    client.send({"op": "subscribe", "topic": "/state"})
    assert client.recv_op("publish", topic="/state")["msg"] == {"data": "ready"}


def test_publish_reaches_the_handler_after_advertise_and_without_it(sample: SampleGraph,
                                                                    client: Client) -> None:
    client.send({"op": "advertise", "topic": "/command", "type": "std_msgs/String"})
    client.send({"op": "publish", "topic": "/command", "msg": {"data": "one"}})
    client.send({"op": "unadvertise", "topic": "/command"})
    # rosbridge infers a known topic's type and advertises it on the way
    client.send({"op": "publish", "topic": "/command", "msg": {"data": "two"}})
    deadline = time.monotonic() + 5
    while len(sample.commands) < 2 and time.monotonic() < deadline:
        time.sleep(0.01)
    assert sample.commands == [{"data": "one"}, {"data": "two"}]


def test_call_service_answers_with_the_request_id_and_values(client: Client) -> None:
    reply = client.call("/add", {"a": 2, "b": 0.5}, ident="call:7")
    assert reply == {"op": "service_response", "service": "/add", "id": "call:7",
                     "values": {"sum": 2.5}, "result": True}


def test_a_failing_service_answers_result_false_with_the_reason(client: Client) -> None:
    reply = client.call("/fail", {})
    assert reply["result"] is False and reply["values"] == "this service always fails"
    reply = client.call("/add", {"a": "x"})
    assert reply["result"] is False and "numbers" in reply["values"]
    reply = client.call("/no_such_service", {})
    assert reply["result"] is False and "does not exist" in reply["values"]


def test_service_calls_answer_out_of_order_by_id(sample: SampleGraph, client: Client) -> None:
    client.send({"op": "call_service", "id": "slow", "service": "/slow", "args": {}})
    fast = client.call("/add", {"a": 1, "b": 1}, ident="fast")
    assert fast["values"] == {"sum": 2}
    sample.release.set()
    assert client.recv_op("service_response", id="slow")["values"]["message"] == "released"


def test_unsubscribe_stops_the_messages(sample: SampleGraph, client: Client) -> None:
    client.send({"op": "subscribe", "id": "a", "topic": "/counter"})
    client.send({"op": "unsubscribe", "id": "a", "topic": "/counter"})
    client.call("/rosapi/get_time")
    sample.graph.publish("/counter", {"data": 1})
    reply = client.call("/add", {"a": 1, "b": 2}, ident="after")
    assert reply["values"] == {"sum": 3}  # and no publish frame came before it (recv_op would
    # have skipped it: check there is nothing left either)
    client.send({"op": "subscribe", "topic": "/counter"})
    client.call("/rosapi/get_time", ident="sync")
    sample.graph.publish("/counter", {"data": 2})
    assert client.recv_op("publish")["msg"] == {"data": 2}


def test_throttle_rate_spaces_messages_and_keeps_the_newest(sample: SampleGraph,
                                                            client: Client) -> None:
    client.send({"op": "subscribe", "topic": "/counter", "throttle_rate": 300,
                 "queue_length": 1})
    client.call("/rosapi/get_time")
    sample.graph.publish("/counter", {"data": -1})
    first = client.recv_op("publish")
    start = time.monotonic()
    for i in range(20):  # within the throttle: only the newest is kept, and waits
        sample.graph.publish("/counter", {"data": i})
    second = client.recv_op("publish")
    assert time.monotonic() - start >= 0.2
    assert first["msg"]["data"] == -1
    assert second["msg"]["data"] == 19  # queue_length 1: the newest waits, the rest dropped


def test_set_level_warning_shows_warnings(client: Client) -> None:
    client.send({"op": "set_level", "level": "warning"})
    client.send({"op": "advertise", "id": "adv", "topic": "/nobody_reads", "type":
                 "std_msgs/String"})
    status = client.recv_op("status", id="adv")
    assert status["level"] == "warning" and "/nobody_reads" in status["msg"]


def test_subscriptions_of_two_clients_are_their_own(sample: SampleGraph, server: object,
                                                    client: Client) -> None:
    other = Client(server.port)  # type: ignore[attr-defined]
    try:
        other.send({"op": "subscribe", "topic": "/counter"})
        other.call("/rosapi/get_time")
        sample.graph.publish("/counter", {"data": 5})
        assert other.recv_op("publish")["msg"] == {"data": 5}
        assert client.call("/add", {"a": 0, "b": 0})["values"] == {"sum": 0}
    finally:
        other.close()
