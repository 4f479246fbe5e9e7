"""The fleet's MQTT transport through a real Mosquitto broker on 127.0.0.1.

Every test waits on the broker with a bound (``WAIT``) and never sleeps: inboxes block until a
message arrives, transports until they are (re)connected and subscribed. Where a test must show
that something did *not* arrive, it sends a sentinel after it on the same connection and waits
for that instead, since the broker keeps each client's messages in order.
"""

from __future__ import annotations

import dataclasses
import os
import signal
import subprocess
import sys

import orjson
import pytest

from polynav.errors import ConfigError, InvalidRequest
from polynav.fleet import codec
from polynav.fleet import messages as m
from polynav.fleet.interface import Transport
from polynav.fleet.mqtt_transport import (
    BrokerUnreachable,
    MqttTransport,
    RawMessage,
    delivery,
)
from tests.conftest import REPO
from tests.helpers.mosquitto import Mosquitto, free_loopback_port, mosquitto_binary
from tests.protocols.fleet_mqtt.conftest import WAIT, TransportFactory


def header(header_id: int, serial: str = "r1") -> m.Header:
    return m.Header(header_id, "2026-11-28T11:40:03.120Z", "2.1.0", "polynav", serial)


ORDER = m.Order(header(1), "r1-1", 0, (
    m.Node("office_1", 0, m.NodePosition(14.3, 20.5, 1.57, "floor1")),
    m.Node("room_201", 2, m.NodePosition(10.2, 19.0, -1.57, "floor2"), released=False),
), (m.Edge("e1", 1, "office_1", "room_201", released=False),))
STATE = m.State(
    header=header(7), order_id="r1-1", order_update_id=0, last_node_id="office_1",
    last_node_sequence_id=0,
    node_states=(m.NodeState("room_201", 2, False, m.NodePosition(10.2, 19.0, 0.0, "floor2")),),
    edge_states=(m.EdgeState("e1", 1, False),), driving=True, operating_mode="AUTOMATIC",
    battery_state=m.BatteryState(81.5, False),
    agv_position=m.AgvPosition(1.0, 2.0, 0.5, "floor1", True, 0.9),
    errors=(m.ErrorEntry("orderFailed", "WARNING", "no path"),),
    floor="floor1", navigation_state="running", waiting_for="zone:floor1/3",
    zones=("zone:floor1/2",),
)
MESSAGES: list[m.Message] = [
    ORDER,
    m.InstantActions(header(3), (m.Action("a1", m.ActionType.CANCEL_ORDER.value),
                                 m.Action("a2", m.ActionType.START_PAUSE.value))),
    m.ZoneRequest(4, "r1", "r1-9", "zone:floor1/3", m.ZoneRequestType.ACCESS, 30.0, flow="E"),
    m.ZoneResponse(5, "r1", "r1-9", "zone:floor1/3", m.GrantType.GRANTED, lease_expiry=42.0),
    STATE,
    m.Visualization(header(8), STATE.agv_position, m.Velocity(0.1, 0.0, 0.0)),
    m.Connection(header(9), m.ConnectionState.ONLINE),
]


def connection(state: str, header_id: int = 1) -> bytes:
    return orjson.dumps({
        "headerId": header_id, "timestamp": "2026-11-28T11:40:03.12Z", "version": "2.1.0",
        "manufacturer": "polynav", "serialNumber": "r1", "connectionState": state,
    })


CONNECTION_TOPIC = "uagv/v2/polynav/r1/connection"


def test_every_codec_message_kind_crosses_the_broker_as_the_codec_bytes(
    connect: TransportFactory,
) -> None:
    assert {type(message) for message in MESSAGES} == set(m.TOPICS)
    fleet, robot = connect("fleet"), connect("robot-r1")
    as_transport: Transport = fleet  # what RobotAgent and MasterControl take (checked by mypy)
    inboxes = {kind: robot.subscribe(m.topic("r1", kind)) for kind in m.TOPICS}
    raw = robot.subscribe_raw("uagv/v2/polynav/r1/#")
    assert robot.wait_subscribed(WAIT)

    for message in MESSAGES:
        as_transport.publish(m.topic("r1", type(message)), message)

    for message in MESSAGES:
        inbox = inboxes[type(message)]
        assert inbox.wait(WAIT)
        assert inbox.drain() == [message]
    received: list[RawMessage] = []
    while len(received) < len(MESSAGES) and raw.wait(WAIT):
        received.extend(raw.drain())
    assert [(r.topic, r.payload, r.qos, r.retain) for r in received] == [
        (m.topic("r1", type(message)), codec.encode(message),
         delivery(m.topic("r1", type(message))).qos, False) for message in MESSAGES
    ]
    assert fleet.stats().published == len(MESSAGES)
    assert robot.stats().received == 2 * len(MESSAGES)
    assert robot.stats().dropped == 0


def test_a_wildcard_subscription_hears_every_robot(connect: TransportFactory) -> None:
    fleet, r1, r2 = connect("fleet"), connect("robot-r1"), connect("robot-r2")
    states = fleet.subscribe("uagv/v2/polynav/+/state")
    assert fleet.wait_subscribed(WAIT)
    other = dataclasses.replace(STATE, header=header(1, "r2"))
    r1.publish(m.topic("r1", m.State), STATE)
    r2.publish(m.topic("r2", m.State), other)
    received: list[m.Message] = []
    while len(received) < 2 and states.wait(WAIT):
        received.extend(states.drain())
    assert sorted(received, key=lambda s: s.serial_number) == [STATE, other]


def test_qos_and_retain_follow_vda5050(connect: TransportFactory) -> None:
    assert (delivery(CONNECTION_TOPIC).qos, delivery(CONNECTION_TOPIC).retain) == (1, True)
    robot, probe = connect("robot-r1"), connect("probe")
    seen = probe.subscribe_raw("uagv/v2/polynav/r1/#")
    assert probe.wait_subscribed(WAIT)
    factsheet = b'{"headerId": 1}'
    robot.publish_raw(CONNECTION_TOPIC, connection("ONLINE"))
    robot.publish_raw("uagv/v2/polynav/r1/factsheet", factsheet)
    robot.publish(m.topic("r1", m.State), STATE)
    robot.publish(m.topic("r1", m.Order), ORDER)
    # The broker orders messages per connection only: once the probe has all four, they are
    # behind it, and a new subscriber can only get them from the retained store.
    passed: list[RawMessage] = []
    while len(passed) < 4 and seen.wait(WAIT):
        passed.extend(seen.drain())
    assert [(r.qos, r.retain) for r in passed] == [(1, False), (0, False), (0, False), (0, False)]

    # A subscriber arriving later gets only what is retained; the sentinel after its SUBACK
    # shows nothing else was coming.
    late = connect("master")
    everything = late.subscribe_raw("uagv/v2/polynav/r1/#")
    assert late.wait_subscribed(WAIT)
    robot.publish_raw("uagv/v2/polynav/r1/visualization", b"{}")
    received: list[RawMessage] = []
    while not any(r.topic.endswith("/visualization") for r in received) and everything.wait(WAIT):
        received.extend(everything.drain())
    assert sorted((r.topic, r.qos, r.retain, r.payload) for r in received) == [
        (CONNECTION_TOPIC, 1, True, connection("ONLINE")),
        ("uagv/v2/polynav/r1/factsheet", 0, True, factsheet),
        ("uagv/v2/polynav/r1/visualization", 0, False, b"{}"),
    ]


def test_mosquitto_sub_sees_what_the_transport_publishes(
    broker: Mosquitto, connect: TransportFactory
) -> None:
    robot = connect("robot-r1")
    tool = mosquitto_binary("mosquitto_sub")
    base = [tool, "-h", "127.0.0.1", "-p", str(broker.port), "-q", "1", "-W", str(int(WAIT)),
            "-F", "%q %r %t %p"]
    # A retained marker tells when mosquitto_sub is subscribed: the broker sends it right after
    # the SUBACK, and mosquitto_sub flushes each message it prints.
    robot.publish_raw("test/ready", b"ready", 1, True)
    with subprocess.Popen([*base, "-C", "3", "-t", "test/ready", "-t", "uagv/v2/polynav/r1/#"],
                          stdout=subprocess.PIPE) as live:
        assert live.stdout is not None
        assert live.stdout.readline() == b"1 1 test/ready ready\n"
        robot.publish(m.topic("r1", m.State), STATE)
        robot.publish_raw(CONNECTION_TOPIC, connection("ONLINE"))
        heard = live.stdout.read().splitlines()
    # Live delivery clears the retain flag (MQTT 3.1.1 §3.3.1.3); QoS is the publisher's.
    assert heard == [
        b"0 0 uagv/v2/polynav/r1/state " + codec.encode(STATE),
        b"1 0 " + CONNECTION_TOPIC.encode() + b" " + connection("ONLINE"),
    ]
    later = subprocess.run([*base, "-C", "1", "-t", CONNECTION_TOPIC], capture_output=True,
                           timeout=WAIT + 5, check=True)
    assert later.stdout == b"1 1 " + CONNECTION_TOPIC.encode() + b" " + connection("ONLINE") + b"\n"


_VEHICLE = """
import sys
from polynav.fleet.mqtt_transport import MqttTransport
url, topic, online, broken, graceful = sys.argv[1:6]
transport = MqttTransport(url, "robot-r1", will=(topic, broken.encode(), 1, True))
transport.publish_raw(topic, online.encode())
print("online", flush=True)
sys.stdin.readline()
if graceful == "yes":
    transport.publish_raw(topic, online.replace("ONLINE", "OFFLINE").encode())
    transport.close()
    print("closed", flush=True)
"""


def _vehicle(broker: Mosquitto, graceful: bool) -> subprocess.Popen[bytes]:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(
        p for p in (str(REPO), os.environ.get("PYTHONPATH")) if p)}
    return subprocess.Popen(
        [sys.executable, "-c", _VEHICLE, broker.url, CONNECTION_TOPIC,
         connection("ONLINE").decode(), connection("CONNECTIONBROKEN").decode(),
         "yes" if graceful else "no"],
        stdin=subprocess.PIPE, stdout=subprocess.PIPE, env=env,
    )


def _states(inbox_messages: list[RawMessage]) -> list[str]:
    return [orjson.loads(r.payload)["connectionState"] for r in inbox_messages]


def test_a_vehicle_killed_without_disconnecting_gets_its_will_published(
    broker: Mosquitto, connect: TransportFactory
) -> None:
    master = connect("master")
    connections = master.subscribe_raw("uagv/v2/+/+/connection", version="2.1.0")
    assert master.wait_subscribed(WAIT)
    with _vehicle(broker, graceful=False) as vehicle:
        assert vehicle.stdout is not None and vehicle.stdout.readline() == b"online\n"
        assert connections.wait(WAIT)
        assert _states(connections.drain()) == ["ONLINE"]
        vehicle.send_signal(signal.SIGKILL)  # the kernel closes the socket: no DISCONNECT
    assert connections.wait(WAIT)
    broken = connections.drain()
    assert _states(broken) == ["CONNECTIONBROKEN"]
    assert (broken[0].qos, broken[0].retain) == (1, False)
    assert master.stats().dropped == 0

    # The will is retained: a master control started afterwards learns the vehicle is gone.
    late = connect("master-2").subscribe_raw(CONNECTION_TOPIC, version="2.1.0")
    assert late.wait(WAIT)
    assert [(r.retain, orjson.loads(r.payload)["connectionState"]) for r in late.drain()] == [
        (True, "CONNECTIONBROKEN")]


def test_a_vehicle_that_disconnects_cleanly_leaves_no_will(
    broker: Mosquitto, connect: TransportFactory
) -> None:
    master = connect("master")
    connections = master.subscribe_raw(CONNECTION_TOPIC, version="2.1.0")
    assert master.wait_subscribed(WAIT)
    with _vehicle(broker, graceful=True) as vehicle:
        assert vehicle.stdout is not None and vehicle.stdout.readline() == b"online\n"
        rest, _ = vehicle.communicate(b"go\n", timeout=WAIT)
    assert (vehicle.returncode, rest) == (0, b"closed\n")
    connect("sentinel").publish_raw(CONNECTION_TOPIC, connection("ONLINE", header_id=9))
    received: list[RawMessage] = []
    while len(received) < 3 and connections.wait(WAIT):
        received.extend(connections.drain())
    assert _states(received) == ["ONLINE", "OFFLINE", "ONLINE"]


def test_after_a_broker_restart_the_transport_resubscribes_and_messages_flow(
    broker: Mosquitto, connect: TransportFactory
) -> None:
    fleet, robot = connect("fleet"), connect("robot-r1")
    orders = robot.subscribe(m.topic("r1", m.Order))
    states = fleet.subscribe(m.topic("r1", m.State))
    assert robot.wait_subscribed(WAIT) and fleet.wait_subscribed(WAIT)
    fleet.publish(m.topic("r1", m.Order), ORDER)
    assert orders.wait(WAIT) and orders.drain() == [ORDER]

    broker.restart()  # a new broker on the same port: no sessions, no subscriptions

    assert robot.wait_subscribed(WAIT) and fleet.wait_subscribed(WAIT)
    later = m.Order(header(2), "r1-2", 0, ORDER.nodes[:1])
    fleet.publish(m.topic("r1", m.Order), later)
    robot.publish(m.topic("r1", m.State), STATE)
    assert orders.wait(WAIT) and orders.drain() == [later]
    assert states.wait(WAIT) and states.drain() == [STATE]
    assert robot.stats().connects == 2 and fleet.stats().connects == 2


def test_malformed_and_schema_breaking_payloads_are_refused_and_counted(
    connect: TransportFactory,
) -> None:
    robot, vandal = connect("robot-r1"), connect("vandal")
    orders = robot.subscribe(m.topic("r1", m.Order))
    connections = robot.subscribe_raw(CONNECTION_TOPIC, version="2.1.0")
    assert robot.wait_subscribed(WAIT)
    order_topic = m.topic("r1", m.Order)
    for bad in (b"{not json", b"\xff\xfe", b"[]", b'{"headerId": "x"}',
                orjson.dumps({**orjson.loads(codec.encode(ORDER)), "nodes": [{"nodeId": 1}]})):
        vandal.publish_raw(order_topic, bad)
    vandal.publish_raw(CONNECTION_TOPIC, connection("SLEEPING"))
    vandal.publish_raw(CONNECTION_TOPIC, b"ONLINE")
    vandal.publish_raw(CONNECTION_TOPIC, connection("ONLINE"))
    vandal.publish(order_topic, ORDER)

    got: list[m.Received] = []
    while ORDER not in got and orders.wait(WAIT):
        got.extend(orders.drain())
    # Fleet-message inboxes hand each refused message over as Rejected (a vehicle reports it);
    # raw inboxes leave them out.
    assert got[-1] == ORDER and len(got) == 6
    fields = [r.field for r in got[:-1] if isinstance(r, m.Rejected)]
    assert fields[:4] == ["message", "message", "order", "order.version"]
    assert fields[4].startswith("$.nodes[0].")  # a node of an otherwise good order
    assert connections.wait(WAIT)
    assert [r.payload for r in connections.drain()] == [connection("ONLINE")]
    assert (orders.dropped, connections.dropped) == (5, 2)
    stats = robot.stats()
    assert (stats.dropped, stats.received) == (7, 2)
    assert robot.connected


def test_an_unreachable_broker_at_start_up_is_a_clear_error() -> None:
    url = f"mqtt://127.0.0.1:{free_loopback_port()}"
    with pytest.raises(BrokerUnreachable) as caught:
        MqttTransport(url, "robot-r1", connect_timeout=0.5)
    assert caught.value.url == url
    assert str(caught.value).startswith(f"MQTT broker at {url} not reachable after 0.5 s: ")
    assert "Connection refused" in caught.value.reason


@pytest.mark.parametrize("url", [
    "tcp://127.0.0.1:1883", "mqtt://", "mqtt://127.0.0.1:99999", "mqtt://host/path",
    "127.0.0.1:1883",
])
def test_a_bad_url_is_a_config_error(url: str) -> None:
    with pytest.raises(ConfigError) as caught:
        MqttTransport(url, "robot-r1", connect_timeout=0.5)
    assert caught.value.key == "fleet.mqtt.url"


def test_bad_topics_filters_and_qos_are_invalid_requests(connect: TransportFactory) -> None:
    robot = connect("robot-r1")
    for topic in ("", "uagv/+/state", "uagv/#"):
        with pytest.raises(InvalidRequest) as caught:
            robot.publish_raw(topic, b"{}")
        assert caught.value.field == "topic"
    for topic_filter in ("", "uagv/#/state", "uagv/r+/state", "uagv/#x"):
        with pytest.raises(InvalidRequest):
            robot.subscribe(topic_filter)
    with pytest.raises(InvalidRequest) as caught:
        robot.publish_raw("uagv/v2/polynav/r1/state", b"{}", qos=3)
    assert caught.value.field == "qos"
    with pytest.raises(InvalidRequest) as caught:
        robot.subscribe_raw("uagv/v2/polynav/r1/state", version="3.0.0")
    assert caught.value.field == "version"
    with pytest.raises(ConfigError):
        connect("robot-r2", will=("uagv/+/connection", b"{}", 1, True))
    assert robot.stats().published == 0


def test_while_the_broker_is_away_qos0_is_lost_and_the_retained_connection_arrives_later(
    broker: Mosquitto, connect: TransportFactory
) -> None:
    robot, master = connect("robot-r1"), connect("master")
    connections = master.subscribe_raw(CONNECTION_TOPIC, version="2.1.0")
    assert master.wait_subscribed(WAIT)
    broker.stop()
    assert robot.wait_disconnected(WAIT)

    robot.publish(m.topic("r1", m.State), STATE)  # QoS 0: lost, and counted as such
    robot.publish_raw(CONNECTION_TOPIC, connection("ONLINE"))  # QoS 1: queued for the broker
    assert (robot.stats().published, robot.stats().unsent) == (1, 1)

    broker.restart()
    assert robot.wait_subscribed(WAIT) and master.wait_subscribed(WAIT)
    assert connections.wait(WAIT)  # live, or from the retained store if the master came later
    assert _states(connections.drain()) == ["ONLINE"]
