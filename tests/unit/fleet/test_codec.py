"""Fleet messages to VDA 5050 JSON and back."""

from __future__ import annotations

import orjson
import pytest

from polynav.errors import InvalidRequest
from polynav.fleet import codec
from polynav.fleet import messages as m

ORDER = m.Order(1, "robot1", "robot1-1", 0, (
    m.Node("office_1", 0, m.NodePosition(14.3, 20.5, 1.57, "floor1")),
    m.Node("room_201", 2, m.NodePosition(10.2, 19.0, 1.57, "floor2"), released=False),
))
STATE = m.State(
    header_id=7, serial_number="robot2", timestamp=12.5, order_id="robot2-3", order_update_id=0,
    last_node_id="lobby", node_states=("kitchen",), driving=True, paused=False,
    operating_mode="AUTOMATIC",
    agv_position=m.AgvPosition(1.0, 2.0, 0.5, "floor1", True, 0.9), battery_charge=81.5,
    errors=(m.ErrorEntry("orderFailed", "WARNING", "no path"),), floor="floor1",
    navigation_state="running", waiting_for="zone:floor1/3", zones=("zone:floor1/2",),
)


@pytest.mark.parametrize("message", [
    ORDER,
    STATE,
    m.InstantActions(3, "robot1", (m.Action("a1", m.ActionType.CANCEL_ORDER),)),
    m.ZoneRequest(4, "robot1", "robot1-9", "zone:floor1/3", m.ZoneRequestType.ACCESS, 30.0),
    m.ZoneRequest(4, "robot1", "robot1-9", "zone:floor1/3", m.ZoneRequestType.ACCESS, 30.0,
                  "E"),
    m.ZoneResponse(5, "robot1", "robot1-9", "zone:floor1/3", m.GrantType.GRANTED, 42.0),
    m.ZoneResponse(6, "robot1", "robot1-9", "zone:floor1/3", m.GrantType.QUEUED),
    m.ZoneResponse(7, "robot1", "robot1-9", "zone:floor1/3", m.GrantType.QUEUED,
                   queue_position=2),
])
def test_every_message_survives_the_round_trip(message: m.Message) -> None:
    kind = m.TOPICS[type(message)]
    assert codec.decode(kind, codec.encode(message)) == message


def test_json_uses_vda_5050_camel_case_names() -> None:
    raw = orjson.loads(codec.encode(ORDER))
    assert set(raw) == {"headerId", "serialNumber", "orderId", "orderUpdateId", "nodes"}
    assert raw["nodes"][0] == {"nodeId": "office_1", "sequenceId": 0, "released": True,
                               "nodePosition": {"x": 14.3, "y": 20.5, "theta": 1.57,
                                                "mapId": "floor1"}}
    queued = m.ZoneResponse(7, "r", "q", "z", m.GrantType.QUEUED, queue_position=2)
    assert orjson.loads(codec.encode(queued))["queuePosition"] == 2
    state = orjson.loads(codec.encode(STATE))
    assert state["agvPosition"]["positionInitialized"] is True
    assert state["errors"][0]["errorType"] == "orderFailed"


@pytest.mark.parametrize("kind, data, field", [
    ("order", b"{", "message"),
    ("order", b"[]", "order"),
    ("order", b'{"headerId": 1}', "order.serialNumber"),
    ("order", b'{"headerId": true, "serialNumber": "r", "orderId": "o", "orderUpdateId": 0,'
              b' "nodes": []}', "order.headerId"),
    ("order", b'{"headerId": 1, "serialNumber": "r", "orderId": "o", "orderUpdateId": 0,'
              b' "nodes": {}}', "order.nodes"),
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
