"""``fragment``: a client's message in pieces is put back together; a subscriber that asks for
``fragment_size`` gets long messages in pieces."""

from __future__ import annotations

import json

from tests.protocols.rosbridge.conftest import Client, SampleGraph


def _pieces(frame: dict[str, object], size: int, ident: str) -> list[dict[str, object]]:
    text = json.dumps(frame)
    chunks = [text[i:i + size] for i in range(0, len(text), size)]
    return [{"op": "fragment", "id": ident, "data": c, "num": n, "total": len(chunks)}
            for n, c in enumerate(chunks)]


def test_a_fragmented_service_call_is_answered(client: Client) -> None:
    pieces = _pieces({"op": "call_service", "id": "f1", "service": "/add",
                      "args": {"a": 40, "b": 2}}, 10, "frag-1")
    for piece in reversed(pieces):  # any order
        client.send(piece)
    assert client.recv_op("service_response", id="f1")["values"] == {"sum": 42}


def test_a_subscriber_gets_long_messages_in_pieces(sample: SampleGraph, client: Client) -> None:
    client.send({"op": "subscribe", "topic": "/state", "fragment_size": 16})
    client.call("/rosapi/get_time")
    sample.graph.publish("/state", {"data": "x" * 100})
    first = client.recv_op("fragment")
    pieces = [first] + [client.recv_op("fragment", id=first["id"])
                        for _ in range(first["total"] - 1)]
    assert [p["num"] for p in pieces] == list(range(first["total"]))
    assert all(len(p["data"]) <= 16 for p in pieces)
    whole = json.loads("".join(p["data"] for p in pieces))
    assert whole == {"op": "publish", "topic": "/state", "msg": {"data": "x" * 100}}


def test_bad_fragments_are_status_errors(client: Client) -> None:
    client.send({"op": "fragment", "id": "b", "data": "{", "num": 3, "total": 2})
    assert "out of range" in client.recv_op("status")["msg"]
    client.send({"op": "fragment", "id": "b", "data": 5, "num": 0, "total": 1})
    assert "'data'" in client.recv_op("status")["msg"]
    client.send({"op": "fragment", "id": "c", "data": "{not json", "num": 0, "total": 1})
    assert "invalid JSON" in client.recv_op("status")["msg"]
    assert client.call("/add", {"a": 1, "b": 1})["values"] == {"sum": 2}  # still served


def test_half_sent_messages_are_bounded(client: Client) -> None:
    for i in range(16):
        client.send({"op": "fragment", "id": f"open-{i}", "data": "{", "num": 0, "total": 2})
    client.send({"op": "fragment", "id": "one-too-many", "data": "{", "num": 0, "total": 2})
    assert "half-sent" in client.recv_op("status")["msg"]
