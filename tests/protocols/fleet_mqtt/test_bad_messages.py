"""Bad input on every topic a robot or the master control subscribes to (issue #36 item 5),
over a real Mosquitto: malformed JSON, non-UTF-8 bytes, schema breaches, wrong header types,
out-of-range numbers, unknown actions, an order of 10,000 nodes, a 2 MB payload.

Each is answered as the standard says (an error in the robot's state: validationError,
noRouteError; a FAILED action state) or with a log line, never a crash: after each, the robot
still answers an instant action over the wire and the master control still reads its state;
after them all, the robot drives a good order to its end.

One building (one robot and the master control, each its own MQTT client) serves the module:
starting one per case would cost more than the cases.
"""

from __future__ import annotations

import itertools
import logging
import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import orjson
import paho.mqtt.client as paho
import pytest
from paho.mqtt.enums import CallbackAPIVersion

from polynav.fleet import codec
from polynav.fleet import messages as m
from polynav.fleet.mqtt_transport import MqttTransport
from polynav.fleet.vehicle import VehicleConfig
from polynav.house.building import Building
from polynav.runtime.config import RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds import load_world
from tests.helpers.mosquitto import Mosquitto

VERSION = "2.0.0"
BASE = "uagv/v2/polynav/robot1"
ROBOT_TOPICS = ("order", "instantActions", "zoneResponse")
"""What a robot's agent subscribes to."""
MASTER_TOPICS = ("state", "zoneRequest")
"""What the current MasterControl subscribes to, per robot (it reads no connection topic)."""
_ids = itertools.count(1000)


class Site:
    """The module's building, and a rogue client that publishes on its topics."""

    def __init__(self, tmp: Path) -> None:
        self.broker = Mosquitto(tmp)
        self.broker.start()
        world = load_world("demo")
        self.store = SiteStore.open(tmp / "data", seed_world=world)
        self.building = Building(self.store, world, robots=1,
                                 config=RuntimeConfig(people=False),
                                 vehicles=VehicleConfig(self.broker.url, version=VERSION,
                                                        visualization_period=None))
        self.rogue = paho.Client(CallbackAPIVersion.VERSION2, client_id="rogue",
                                 protocol=paho.MQTTv311)
        connected = threading.Event()
        self.rogue.on_connect = lambda *args: connected.set()
        self.rogue.connect("127.0.0.1", self.broker.port)
        self.rogue.loop_start()
        assert connected.wait(10.0)

    def publish(self, topic: str, payload: bytes) -> None:
        self.rogue.publish(f"{BASE}/{topic}", payload, qos=1).wait_for_publish(10.0)

    def run_until(self, done: Callable[[], bool], wall: float = 10.0) -> bool:
        """Run the building, 2 ms of wall time per control period, until ``done()``; at most
        ``wall`` seconds of wall time."""
        deadline = time.monotonic() + wall

        def over() -> bool:
            time.sleep(0.002)
            return done() or time.monotonic() > deadline

        self.building.advance_until(over, timeout=3600.0)
        return done()

    def state(self) -> m.State:
        state = self.building.master.state("robot1")
        assert state is not None
        return state

    def instant(self, action_type: str, parameters: list[dict[str, Any]] | None = None) -> str:
        action_id = f"a{next(_ids)}"
        action: dict[str, Any] = {"actionId": action_id, "actionType": action_type,
                                  "actionName": action_type, "blockingType": "NONE"}
        if parameters is not None:
            action["actionParameters"] = parameters
        self.publish("instantActions", orjson.dumps({**header(), "actions": [action]}))
        return action_id

    def action_status(self, action_id: str) -> str | None:
        for action in self.state().action_states:
            if action.action_id == action_id:
                return action.action_status.value
        return None

    def close(self) -> None:
        self.rogue.disconnect()
        self.rogue.loop_stop()
        self.building.close()
        self.store.close()
        self.broker.stop()


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Site]:
    opened = Site(tmp_path_factory.mktemp("bad_messages"))
    yield opened
    opened.close()


def header() -> dict[str, Any]:
    return {"headerId": next(_ids), "timestamp": "2026-11-28T12:00:00.000Z",
            "version": VERSION, "manufacturer": "polynav", "serialNumber": "robot1"}


def order(nodes: list[tuple[float, float]], action: str | None = None) -> dict[str, Any]:
    node_list = [{"nodeId": f"n{k}", "sequenceId": 2 * k, "released": True,
                  "actions": [], "nodePosition": {"x": x, "y": y, "mapId": "floor1"}}
                 for k, (x, y) in enumerate(nodes)]
    if action is not None:
        node_list[-1]["actions"] = [{"actionId": "x", "actionType": action,
                                     "blockingType": "HARD"}]
    edges = [{"edgeId": f"e{k}", "sequenceId": 2 * k + 1, "released": True,
              "startNodeId": f"n{k}", "endNodeId": f"n{k + 1}", "actions": []}
             for k in range(len(nodes) - 1)]
    return {**header(), "orderId": f"o{next(_ids)}", "orderUpdateId": 0, "nodes": node_list,
            "edges": edges}


def good(topic: str) -> dict[str, Any]:
    """A well-formed message of ``topic`` (as a robot or the master would send it)."""
    if topic == "order":
        return order([(8.0, 8.5), (5.5, 12.5)])
    if topic == "instantActions":  # where the robot starts (numbers for the cases to spoil)
        return {**header(), "actions": [{
            "actionId": "g", "actionType": "initPosition", "actionName": "initPosition",
            "blockingType": "NONE", "actionParameters": [
                {"key": "x", "value": 8.0}, {"key": "y", "value": 8.5},
                {"key": "theta", "value": 0.0}, {"key": "mapId", "value": "floor1"}]}]}
    if topic == "zoneResponse":
        return dict(orjson.loads(codec.encode(m.ZoneResponse(
            next(_ids), "robot1", "robot1-9999", "zone-9", m.GrantType.GRANTED, 5.0, None))))
    if topic == "zoneRequest":
        return dict(orjson.loads(codec.encode(m.ZoneRequest(
            next(_ids), "robot1", "robot1-9999", "zone-9", m.ZoneRequestType.ACCESS, 30.0,
            "EE"))))
    state = orjson.loads(codec.encode(dataclass_state()))
    return dict(state)


def dataclass_state() -> m.State:
    stamp = m.Header(next(_ids), "2026-11-28T12:00:00.000Z", VERSION, "polynav", "robot1")
    return m.State(header=stamp, order_id="", order_update_id=0, last_node_id="",
                   last_node_sequence_id=0, node_states=(), edge_states=(), driving=False,
                   operating_mode="AUTOMATIC", battery_state=m.BatteryState(80.0, False),
                   paused=False, agv_position=m.AgvPosition(8.0, 8.5, 0.0, "floor1", True, 1.0),
                   velocity=m.Velocity(0.0, 0.0, 0.0), errors=(), action_states=(),
                   safety_state=m.SafetyState("NONE", False))


_HEADER_KEYS = ("headerId", "timestamp", "version", "manufacturer", "serialNumber")


def _numbers(value: Any, to: float) -> Any:
    if isinstance(value, dict):
        return {k: v if k == "headerId" else _numbers(v, to) for k, v in value.items()}
    if isinstance(value, list):
        return [_numbers(v, to) for v in value]
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return to
    return value


def _with(topic: str, **fields: Any) -> bytes:
    return orjson.dumps({**good(topic), **fields})


GENERIC: dict[str, Callable[[str], bytes]] = {
    "malformed_json": lambda t: b'{"headerId": 1, "nodes": [',
    "non_utf8": lambda t: b'{"headerId": 1, "orderId": "\xff\xfe\xfd"}',
    "raw_binary": lambda t: bytes(range(256)) * 4,
    "empty": lambda t: b"",
    "not_an_object": lambda t: b"[1, 2, 3]",
    "nan_literal": lambda t: b'{"headerId": NaN}',
    "too_deep": lambda t: b"[" * 5000 + b"]" * 5000,
    "header_id_string": lambda t: _with(t, headerId="seven"),
    "header_id_float": lambda t: _with(t, headerId=1.5),
    "header_id_huge": lambda t: orjson.dumps(good(t)).replace(
        b'"headerId":', b'"headerId":123456789012345678901234567890,"x":', 1),
    "wrong_types": lambda t: orjson.dumps({k: (v if k in _HEADER_KEYS else {"bad": [True]})
                                           for k, v in good(t).items()}),
    "huge_numbers": lambda t: orjson.dumps(_numbers(good(t), 1e308)),
    "negative_huge_numbers": lambda t: orjson.dumps(_numbers(good(t), -1e308)),
    "infinity_by_overflow": lambda t: orjson.dumps(good(t)).replace(
        b'"headerId":', b'"x":1e400,"headerId":', 1),
    "payload_2mb": lambda t: _with(t, padding="x" * 2_000_000),
}

SPECIFIC: dict[tuple[str, str], Callable[[], bytes]] = {
    ("order", "order_10000_nodes"): lambda: orjson.dumps(
        order([(8.0 + 0.001 * k, 8.5) for k in range(10_000)])),
    ("order", "order_1500_nodes_under_2mb"): lambda: orjson.dumps(
        order([(8.0 + 0.001 * k, 8.5) for k in range(1500)])),
    ("order", "node_far_out_of_range"): lambda: orjson.dumps(
        order([(8.0, 8.5), (1e308, -1e308)])),
    ("order", "node_beyond_the_map"): lambda: orjson.dumps(order([(8.0, 8.5), (5000.0, 8.5)])),
    ("order", "unknown_node_action"): lambda: orjson.dumps(
        order([(8.0, 8.5), (5.5, 12.5)], action="selfDestruct")),
    ("order", "unknown_map"): lambda: orjson.dumps(
        {**order([(8.0, 8.5)]), "nodes": [{"nodeId": "n0", "sequenceId": 0, "released": True,
                                            "actions": [], "nodePosition": {
                                                "x": 8.0, "y": 8.5, "mapId": "mars"}}]}),
    ("order", "ids_of_300_kb"): lambda: orjson.dumps(
        {**order([(8.0, 8.5), (5.5, 12.5)]), "orderId": "o" * 300_000}),
    ("order", "wrong_types_of_300_kb"): lambda: orjson.dumps(
        {**order([(8.0, 8.5)]), "orderId": "o" * 200_000, "nodes": {"bad": ["x" * 200_000]}}),
    ("instantActions", "unknown_action_type"): lambda: orjson.dumps(
        {**header(), "actions": [{"actionId": "u1", "actionType": "selfDestruct",
                                  "actionName": "selfDestruct", "blockingType": "NONE"}]}),
    ("instantActions", "init_position_huge"): lambda: orjson.dumps(
        {**header(), "actions": [{"actionId": "u2", "actionType": "initPosition",
                                  "actionName": "initPosition", "blockingType": "NONE",
                                  "actionParameters": [
                                      {"key": "x", "value": 1e308}, {"key": "y", "value": 0},
                                      {"key": "theta", "value": 0},
                                      {"key": "mapId", "value": "floor1"}]}]}),
    ("zoneResponse", "unknown_grant_type"): lambda: _with("zoneResponse", grantType="MAYBE"),
    ("zoneRequest", "unknown_request_type"): lambda: _with("zoneRequest", requestType="STEAL"),
    ("zoneRequest", "lease_of_1e308_seconds"): lambda: _with("zoneRequest", duration=1e308),
    ("state", "10000_node_states"): lambda: _with("state", nodeStates=[
        {"nodeId": f"n{k}", "sequenceId": 2 * k, "released": True} for k in range(10_000)]),
}

FOREIGN = {("zoneResponse", "huge_numbers"), ("zoneResponse", "negative_huge_numbers")}
"""Cases that stay well-formed: an answer to a zone request this robot never made (a lease
expiry of +-1e308 s), which the robot ignores as it ignores any stale answer."""

CASES = [(topic, name, (lambda f=make, t=topic: f(t)))
         for topic in (*ROBOT_TOPICS, *MASTER_TOPICS) for name, make in GENERIC.items()] + [
    (topic, name, make) for (topic, name), make in SPECIFIC.items()]


def _warned(caplog: pytest.LogCaptureFixture) -> list[str]:
    return [r.getMessage() for r in caplog.records
            if r.levelno >= logging.WARNING and r.name.startswith("polynav.")]


@pytest.mark.parametrize(("topic", "name", "make"), CASES,
                         ids=[f"{t}-{n}" for t, n, _ in CASES])
def test_a_bad_message_is_answered_or_logged_and_the_robot_goes_on(
        site: Site, caplog: pytest.LogCaptureFixture, topic: str, name: str,
        make: Callable[[], bytes]) -> None:
    caplog.set_level(logging.WARNING)
    payload = make()
    site.publish(topic, payload)
    if (topic, name) in FOREIGN:
        site.run_until(lambda: False, wall=0.3)
        assert site.building.agent("robot1").traffic.held == ()
    elif topic in ("order", "instantActions"):
        # The robot answers in its state, with the standard's error types or a FAILED action.
        def answered() -> bool:
            said = [w for w in _warned(caplog) if w.startswith("robot1: ")]
            return bool(said) and any(
                e.error_type in ("validationError", "noRouteError")
                for e in site.state().errors) or any(
                "failed" in w for w in said)
        assert site.run_until(answered), (_warned(caplog), site.state().errors)
        if topic == "instantActions" and not any(
                e.error_type == "validationError" for e in site.state().errors):
            sent = {a.get("actionId") for a in orjson.loads(payload).get("actions", [])
                    if isinstance(a, dict)}

            def failed() -> bool:
                return any(a.action_id in sent and a.action_status is m.ActionStatus.FAILED
                           for a in site.state().action_states)
            # The warning is logged as the action fails; the state saying so follows over the
            # broker.
            assert site.run_until(failed), site.state().action_states
    else:
        assert site.run_until(lambda: bool(_warned(caplog))), topic
    # Never a crash: the robot still hears an instant action, carries it out, and the master
    # control reads the state that says so; every client is still connected.
    ask = site.instant("stateRequest")
    assert site.run_until(lambda: site.action_status(ask) == "FINISHED"), _warned(caplog)
    # What the state echoes of a bad message is cut short (a state must stay readable).
    for error in site.state().errors:
        assert len(error.error_description) < 300
        assert all(len(r.reference_value) < 300 for r in error.error_references)
    assert all(len(w) < 1000 for w in _warned(caplog))
    clients = [site.building.transport, *(link.transport for link in site.building.links)]
    assert all(isinstance(c, MqttTransport) and c.connected for c in clients)


def test_after_every_bad_message_the_robot_still_drives_a_good_order(site: Site) -> None:
    for topic, _, make in CASES:  # all of them again, back to back, before the good order
        site.publish(topic, make())
    ask = site.instant("stateRequest")  # after them on the wire: they have all been read
    assert site.run_until(lambda: site.action_status(ask) == "FINISHED")
    site.run_until(lambda: False, wall=0.5)
    sent = site.building.send("robot1", "lobby", "floor1")

    def ended() -> bool:  # and the master has heard so
        return site.building.outcome("robot1", sent) is not None and (
            site.state().order_id == sent and not site.state().node_states)

    assert site.run_until(ended, wall=60.0)
    assert site.building.outcome("robot1", sent) == "succeeded"
    state = site.state()
    assert (state.order_id, state.node_states) == (sent, ())
    assert state.errors == ()
