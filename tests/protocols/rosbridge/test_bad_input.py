"""Bad input gets rosbridge's answer (a ``status`` error, or ``result: false``), the connection
kept where rosbridge keeps it and the server unaffected for everyone else."""

from __future__ import annotations

import json
import os
import socket
import time

import pytest
from websockets.exceptions import ConnectionClosed

from polynav.protocols.rosbridge import RosbridgeThread
from tests.protocols.rosbridge.conftest import Client, SampleGraph, rosbridge


def _error(client: Client, frame: object, ident: str | None = None) -> str:
    client.send(frame)
    status = client.recv_op("status") if ident is None else client.recv_op("status", id=ident)
    assert status["level"] == "error"
    return str(status["msg"])


@pytest.mark.parametrize(("frame", "words"), [
    ({"op": "dance"}, "unknown op"),
    ({"topic": "/counter"}, "'op'"),
    ([1, 2, 3], "JSON object"),
    ({"op": 5}, "'op'"),
    ({"op": "subscribe"}, "missing 'topic'"),
    ({"op": "subscribe", "topic": 7}, "'topic' must be a string"),
    ({"op": "subscribe", "topic": "/counter", "type": "std_msgs/String"}, "is of type"),
    ({"op": "subscribe", "topic": "/counter", "throttle_rate": "fast"}, "'throttle_rate'"),
    ({"op": "subscribe", "topic": "/counter", "queue_length": -1}, "'queue_length'"),
    ({"op": "subscribe", "topic": "/unknown"}, "cannot infer topic type"),
    ({"op": "publish", "topic": "/elsewhere", "msg": {}}, "not yet advertised"),
    ({"op": "publish", "topic": "/command"}, "'msg'"),
    ({"op": "publish", "topic": "/command", "msg": "text"}, "'msg'"),
    ({"op": "advertise", "topic": "/command", "type": "geometry_msgs/Twist"}, "is of type"),
    ({"op": "advertise", "topic": "/command"}, "missing 'type'"),
    ({"op": "advertise_service", "service": "/mine", "type": "std_srvs/Trigger"},
     "hosts no services"),
    ({"op": "set_level", "level": "loud"}, "'level'"),
    ({"op": "png", "data": "iVBORw0KGgo="}, "png"),
    ({"op": "call_service"}, "missing 'service'"),
])
def test_a_bad_op_is_a_status_error_and_the_connection_stays(client: Client, frame: object,
                                                              words: str) -> None:
    assert words in _error(client, frame)
    assert client.call("/add", {"a": 1, "b": 2})["values"] == {"sum": 3}


def test_the_status_carries_the_ops_id(client: Client) -> None:
    msg = _error(client, {"op": "subscribe", "id": "mine-1", "topic": 3}, ident="mine-1")
    assert "'topic'" in msg


def test_invalid_json_and_binary_frames_are_status_errors(client: Client) -> None:
    assert "invalid JSON" in _error(client, "{op: subscribe")
    assert "binary" in _error(client, b"\x00\x01\x02")
    assert client.call("/add", {"a": 1, "b": 2})["values"] == {"sum": 3}


def test_a_published_message_the_handler_refuses_is_a_status_error(sample: SampleGraph,
                                                                    client: Client) -> None:
    msg = _error(client, {"op": "publish", "id": "p", "topic": "/command", "msg": {"data": 5}},
                 ident="p")
    assert "'data' must be a string" in msg
    assert sample.commands == []


def test_service_call_with_bad_args_is_result_false(client: Client) -> None:
    reply = client.call("/add", ["positional"])
    assert reply["result"] is False and "'args'" in reply["values"]
    reply = client.call("/add", {"a": 1})
    assert reply["result"] is False


def test_a_ten_megabyte_message_is_refused_and_the_server_goes_on(server: RosbridgeThread,
                                                                  client: Client) -> None:
    big = {"op": "publish", "id": "big", "topic": "/command", "msg": {"data": 7,
                                                                     "pad": "x" * 10_000_000}}
    assert "'data' must be a string" in _error(client, big, ident="big")
    assert client.call("/add", {"a": 1, "b": 2})["values"] == {"sum": 3}
    client.send("x" * (11 * 1024 * 1024))  # beyond the 10 MiB frame limit: closed, 1009
    with pytest.raises(ConnectionClosed) as closed:
        client.recv(timeout=10)
    assert closed.value.rcvd is not None and closed.value.rcvd.code == 1009
    other = Client(server.port)
    try:
        assert other.call("/add", {"a": 2, "b": 2})["values"] == {"sum": 4}
    finally:
        other.close()


def test_a_client_that_never_reads_is_closed_and_costs_a_bounded_amount(
        sample: SampleGraph) -> None:
    with rosbridge(sample.graph, sample.clock, send_timeout=1.0) as server:
        raw = socket.create_connection(("127.0.0.1", server.port))
        try:
            raw.sendall(b"GET / HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\nConnection: "
                        b"Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n"
                        b"Sec-WebSocket-Version: 13\r\n\r\n")
            assert raw.recv(4096).startswith(b"HTTP/1.1 101")
            # One masked client frame subscribing to /counter, then never another read.
            payload = json.dumps({"op": "subscribe", "topic": "/counter",
                                  "queue_length": 5}).encode()
            mask = os.urandom(4)
            raw.sendall(bytes([0x81, 0x80 | len(payload)]) + mask
                        + bytes(b ^ mask[i % 4] for i, b in enumerate(payload)))
            deadline = time.monotonic() + 5
            while server.server.clients != 1 and time.monotonic() < deadline:
                time.sleep(0.01)
            big = "y" * 50_000
            deadline = time.monotonic() + 30
            while server.server.clients and time.monotonic() < deadline:
                sample.graph.publish("/counter", {"data": 1, "pad": big})  # 50 kB each
                time.sleep(0.002)
            assert server.server.clients == 0, "the server kept a client that does not read"
            other = Client(server.port)
            try:
                assert other.call("/add", {"a": 1, "b": 1})["values"] == {"sum": 2}
            finally:
                other.close()
        finally:
            raw.close()
