"""Fleet messages to VDA 5050 JSON and back, checked against the official schemas both ways."""

from __future__ import annotations

import datetime as dt

import orjson
import pytest

from polynav.errors import InvalidRequest
from polynav.fleet import codec
from polynav.fleet import messages as m
from polynav.fleet.vda5050 import validation
from polynav.fleet.vda5050.validation import SchemaViolation


def header(header_id: int, version: str = "2.1.0", serial: str = "robot1") -> m.Header:
    return m.Header(header_id, "2026-11-28T11:40:03.120Z", version, "polynav", serial)


def order(version: str = "2.1.0") -> m.Order:
    return m.Order(header(1, version), "robot1-1", 0, (
        m.Node("office_1", 0, m.NodePosition(14.3, 20.5, 1.57, "floor1")),
        m.Node("room_201", 2, m.NodePosition(10.2, 19.0, None, "floor2"), released=False),
    ), (m.Edge("e1", 1, "office_1", "room_201", released=False),))


def state(version: str = "2.1.0") -> m.State:
    return m.State(
        header=header(7, version, "robot2"), order_id="robot2-3", order_update_id=0,
        last_node_id="lobby", last_node_sequence_id=0,
        node_states=(m.NodeState("kitchen", 2, True, m.NodePosition(3.0, 4.0, 0.0, "floor1")),),
        edge_states=(m.EdgeState("lobby->kitchen", 1, True),), driving=True,
        operating_mode="AUTOMATIC", battery_state=m.BatteryState(81.5, False),
        agv_position=m.AgvPosition(1.0, 2.0, 0.5, "floor1", True, 0.9),
        velocity=m.Velocity(0.4, 0.0, 0.1),
        errors=(m.ErrorEntry("orderFailed", "WARNING", "no path",
                             (m.ErrorReference("orderId", "robot2-3"),)),),
        action_states=(m.ActionState("a1", m.ActionStatus.FINISHED, "cancelOrder"),),
        floor="floor1", navigation_state="running", waiting_for="zone:floor1/3",
        zones=("zone:floor1/2",),
    )


def instant(version: str = "2.1.0") -> m.InstantActions:
    return m.InstantActions(header(3, version), (
        m.Action("a1", "cancelOrder"),
        m.Action("a2", "initPosition", m.BlockingType.HARD, (
            m.ActionParameter("x", 1.5), m.ActionParameter("mapId", "floor1"))),
    ))


MESSAGES: list[m.Message] = [
    order(), order("2.0.0"), state(), state("2.0.0"), instant(), instant("2.0.0"),
    m.Connection(header(9), m.ConnectionState.ONLINE),
    m.Visualization(header(10), m.AgvPosition(1.0, 2.0, 0.5, "floor1", True),
                    m.Velocity(0.0, 0.0, 0.0)),
    m.ZoneRequest(4, "robot1", "robot1-9", "zone:floor1/3", m.ZoneRequestType.ACCESS, 30.0),
    m.ZoneRequest(4, "robot1", "robot1-9", "zone:floor1/3", m.ZoneRequestType.ACCESS, 30.0,
                  "E"),
    m.ZoneResponse(5, "robot1", "robot1-9", "zone:floor1/3", m.GrantType.GRANTED, 42.0),
    m.ZoneResponse(6, "robot1", "robot1-9", "zone:floor1/3", m.GrantType.QUEUED),
    m.ZoneResponse(7, "robot1", "robot1-9", "zone:floor1/3", m.GrantType.QUEUED,
                   queue_position=2),
]


@pytest.mark.parametrize("message", MESSAGES)
def test_every_message_survives_the_round_trip(message: m.Message) -> None:
    kind = m.TOPICS[type(message)]
    assert codec.decode(kind, codec.encode(message)) == message


@pytest.mark.parametrize("message", [x for x in MESSAGES if hasattr(x, "header")])
def test_every_vda_message_polynav_writes_passes_the_official_schema(message: m.Message) -> None:
    kind = m.TOPICS[type(message)]
    raw = orjson.loads(codec.encode(message))
    validation.validate(kind, raw["version"], raw)
    assert raw["headerId"] >= 0 and raw["manufacturer"] == "polynav"


def test_json_uses_vda_5050_names_and_leaves_out_what_is_none() -> None:
    raw = orjson.loads(codec.encode(order()))
    assert set(raw) == {"headerId", "timestamp", "version", "manufacturer", "serialNumber",
                        "orderId", "orderUpdateId", "nodes", "edges"}
    assert raw["nodes"][1] == {"nodeId": "room_201", "sequenceId": 2, "released": False,
                               "actions": [],
                               "nodePosition": {"x": 10.2, "y": 19.0, "mapId": "floor2"}}
    assert raw["edges"][0]["startNodeId"] == "office_1"
    queued = m.ZoneResponse(7, "r", "q", "z", m.GrantType.QUEUED, queue_position=2)
    assert orjson.loads(codec.encode(queued))["queuePosition"] == 2
    raw_state = orjson.loads(codec.encode(state()))
    assert raw_state["agvPosition"]["positionInitialized"] is True
    assert raw_state["errors"][0]["errorReferences"] == [
        {"referenceKey": "orderId", "referenceValue": "robot2-3"}]
    assert raw_state["safetyState"] == {"eStop": "NONE", "fieldViolation": False}
    assert raw_state["batteryState"] == {"batteryCharge": 81.5, "charging": False}


def test_2_0_0_instant_actions_carry_both_names_and_either_is_read() -> None:
    raw = orjson.loads(codec.encode(instant("2.0.0")))
    assert [(a["actionType"], a["actionName"]) for a in raw["actions"]] == [
        ("cancelOrder", "cancelOrder"), ("initPosition", "initPosition")]
    for action in raw["actions"]:
        del action["actionType"]  # as a 2.0.0 master following its schema sends it
    decoded = codec.decode("instantActions", orjson.dumps(raw))
    assert decoded == instant("2.0.0")


def test_a_message_that_breaks_its_schema_is_never_sent() -> None:
    bad = m.Order(header(1), "o", -1, order().nodes, order().edges)  # orderUpdateId < 0
    with pytest.raises(SchemaViolation) as err:
        codec.encode(bad)
    assert err.value.path == "$.orderUpdateId"


@pytest.mark.parametrize("kind, data, field", [
    ("order", b"{", "message"),
    ("order", b"[]", "order"),
    ("order", b'{"headerId": 1, "version": "2.1.0"}', "$.timestamp"),
    ("order", b'{"headerId": 1, "version": "1.1.0"}', "order.version"),
    ("zoneResponse", b'{"headerId": 1, "serialNumber": "r", "requestId": "q", "zoneId": "z",'
                     b' "grantType": "MAYBE"}', "zoneResponse.grantType"),
    ("zoneResponse", b'{"headerId": 1, "serialNumber": "r", "requestId": "q", "zoneId": "z",'
                     b' "grantType": "QUEUED", "queuePosition": "2"}',
     "zoneResponse.queuePosition"),
    ("zoneRequest", b'{"headerId": 1, "serialNumber": "r", "requestId": "q", "zoneId": "z",'
                    b' "requestType": "ACCESS", "flow": 3}', "zoneRequest.flow"),
    ("teleport", b"{}", "topic"),
])
def test_bad_messages_are_refused_naming_the_field(kind: str, data: bytes, field: str) -> None:
    with pytest.raises(InvalidRequest) as err:
        codec.decode(kind, data)
    assert err.value.field == field


def test_schema_breaking_order_is_read_as_rejected_with_its_ids() -> None:
    raw = orjson.loads(codec.encode(order()))
    raw["nodes"][0]["sequenceId"] = "zero"
    got = codec.read("order", orjson.dumps(raw))
    assert isinstance(got, m.Rejected)
    assert (got.field, got.header_id, got.order_id) == ("$.nodes[0].sequenceId", 1, "robot1-1")


def test_headers_count_per_topic_and_stamp_utc_with_milliseconds() -> None:
    clock = [12.3456]
    headers = m.Headers("2.1.0", "acme", lambda: clock[0],
                        epoch=dt.datetime(2026, 1, 2, 3, 4, 5, tzinfo=dt.UTC))
    first, second = headers.stamp("r1", m.State), headers.stamp("r1", m.State)
    other = headers.stamp("r1", "factsheet")
    assert (first.header_id, second.header_id, other.header_id) == (0, 1, 0)
    assert first.timestamp == "2026-01-02T03:04:17.345Z"
    assert (first.version, first.manufacturer, first.serial_number) == ("2.1.0", "acme", "r1")
    assert m.topic("r1", m.State, "acme") == "uagv/v2/acme/r1/state"
