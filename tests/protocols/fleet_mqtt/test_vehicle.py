"""A lone polynav robot as a VDA 5050 vehicle on a real Mosquitto, driven by a small master
written here from the standard alone (paho and JSON, no polynav code on its side).

The robot runs on simulated time, advanced in small steps with a short wall pause in between
for the broker to carry what was published; every wait has a bound.
"""

from __future__ import annotations

import subprocess
import threading
import time
from collections.abc import Callable, Iterator
from typing import Any

import orjson
import paho.mqtt.client as paho
import pytest
from paho.mqtt.enums import CallbackAPIVersion

from polynav.fleet.vda5050 import validation
from polynav.fleet.vehicle import LoneVehicle, VehicleConfig
from polynav.runtime.config import RuntimeConfig
from polynav.runtime.robot_runtime import RobotRuntime
from polynav.store.site_store import SiteStore
from polynav.worlds.world import World
from tests.helpers.mosquitto import Mosquitto, mosquitto_binary
from tests.protocols.fleet_mqtt.conftest import WAIT

BASE = "uagv/v2/polynav/r1"
STAMP = "2026-11-28T12:00:00.000Z"


class Master:
    """A master control as the standard describes it: publishes orders and instant actions,
    reads every message the vehicle publishes (JSON, checked against the schemas)."""

    def __init__(self, url: str, version: str) -> None:
        self.version = version
        self.received: list[tuple[str, dict[str, Any]]] = []
        self._lock = threading.Lock()
        self._headers = {"order": 0, "instantActions": 0}
        host, port = url.removeprefix("mqtt://").split(":")
        subscribed = threading.Event()
        self.client = paho.Client(CallbackAPIVersion.VERSION2, client_id="test-master")
        self.client.on_message = self._on_message
        self.client.on_subscribe = lambda *args: subscribed.set()
        self.client.connect(host, int(port))
        self.client.loop_start()
        self.client.subscribe(f"{BASE}/#", qos=1)
        assert subscribed.wait(WAIT)

    def _on_message(self, client: paho.Client, userdata: Any, message: paho.MQTTMessage) -> None:
        topic = message.topic.rsplit("/", 1)[-1]
        if topic in ("order", "instantActions"):  # its own, echoed by the broker
            return
        with self._lock:
            self.received.append((topic, orjson.loads(message.payload)))

    def of(self, topic: str) -> list[dict[str, Any]]:
        with self._lock:
            return [body for name, body in self.received if name == topic]

    def last_state(self) -> dict[str, Any]:
        states = self.of("state")
        assert states, "no state yet"
        return states[-1]

    def header(self, topic: str) -> dict[str, Any]:
        self._headers[topic] += 1
        return {"headerId": self._headers[topic], "timestamp": STAMP, "version": self.version,
                "manufacturer": "polynav", "serialNumber": "r1"}

    def publish(self, topic: str, body: dict[str, Any] | bytes) -> None:
        payload = body if isinstance(body, bytes) else orjson.dumps(body)
        self.client.publish(f"{BASE}/{topic}", payload, qos=0).wait_for_publish(WAIT)

    def order(self, order_id: str, nodes: list[tuple[str, float, float]], *, update: int = 0,
              map_id: str = "floor1", first_sequence: int = 0,
              released: int | None = None) -> dict[str, Any]:
        base = len(nodes) if released is None else released
        node_list = [{"nodeId": name, "sequenceId": first_sequence + 2 * k, "released": k < base,
                      "actions": [], "nodePosition": {"x": x, "y": y, "mapId": map_id}}
                     for k, (name, x, y) in enumerate(nodes)]
        edges = [{"edgeId": f"e{a['sequenceId']}", "sequenceId": a["sequenceId"] + 1,
                  "released": b["released"],
                  "startNodeId": a["nodeId"], "endNodeId": b["nodeId"], "actions": []}
                 for k, (a, b) in enumerate(zip(node_list, node_list[1:], strict=False))]
        return {**self.header("order"), "orderId": order_id, "orderUpdateId": update,
                "nodes": node_list, "edges": edges}

    def instant(self, action_id: str, action_type: str,
                parameters: list[dict[str, Any]] | None = None) -> None:
        action: dict[str, Any] = {"actionId": action_id, "actionType": action_type,
                                  "blockingType": "NONE"}
        if self.version == "2.0.0":
            action["actionName"] = action_type  # 2.0.0's schema names it so
        if parameters:
            action["actionParameters"] = parameters
        self.publish("instantActions", {**self.header("instantActions"), "actions": [action]})

    def close(self) -> None:
        self.client.disconnect()
        self.client.loop_stop()


@pytest.fixture(params=["2.0.0", "2.1.0"])
def version(request: pytest.FixtureRequest) -> str:
    return str(request.param)


@pytest.fixture
def runtime(world: World, store: SiteStore) -> RobotRuntime:
    return RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False))


@pytest.fixture
def master(broker: Mosquitto, version: str) -> Iterator[Master]:
    peer = Master(broker.url, version)
    yield peer
    peer.close()


@pytest.fixture
def vehicle(broker: Mosquitto, runtime: RobotRuntime, version: str) -> Iterator[LoneVehicle]:
    runtime.start_navigation("floor1")
    lone = LoneVehicle(runtime, "r1", VehicleConfig(broker.url, version=version,
                                                    visualization_period=0.5))
    yield lone
    lone.close()


def run_until(runtime: RobotRuntime, done: Callable[[], bool], sim_timeout: float) -> bool:
    """Advance the robot 0.1 s at a time, 2 ms of wall time between, until ``done()``; give up
    after ``sim_timeout`` simulated seconds, but never before 3 s of wall time (a loaded
    machine's broker may take that long to carry a message), nor after 15 s."""
    deadline = runtime.now() + sim_timeout
    started = time.monotonic()
    while not done():
        waited = time.monotonic() - started
        if waited > 15.0 or (runtime.now() >= deadline and waited > 3.0):
            return False
        runtime.advance(0.1)
        time.sleep(0.002)
    return True


def validated(topic: str, body: dict[str, Any], version: str) -> dict[str, Any]:
    validation.validate(topic, version, body)
    assert body["version"] == version and body["serialNumber"] == "r1"
    return body


def test_mosquitto_sub_sees_connection_factsheet_state_and_visualization_all_valid(
        broker: Mosquitto, vehicle: LoneVehicle, runtime: RobotRuntime, version: str) -> None:
    sub = subprocess.Popen(
        [mosquitto_binary("mosquitto_sub"), "-h", "127.0.0.1", "-p", str(broker.port),
         "-t", f"{BASE}/#", "-v", "-W", "15"],
        stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    seen: dict[str, list[dict[str, Any]]] = {}
    lines: list[str] = []

    def read() -> None:
        assert sub.stdout is not None
        for line in sub.stdout:
            lines.append(line)

    reader = threading.Thread(target=read, daemon=True)
    try:

        reader.start()
        time.sleep(0.3)  # mosquitto_sub connects; the retained messages come first
        vehicle.agent.publish_state(runtime.now())  # as after an event
        assert run_until(runtime, lambda: sum("/visualization " in x for x in lines) >= 2, 10.0)
        time.sleep(0.2)
    finally:
        sub.terminate()
        sub.wait(5.0)
        reader.join(5.0)
        assert sub.stdout is not None
        sub.stdout.close()
    for line in lines:
        topic, _, payload = line.partition(" ")
        seen.setdefault(topic.rsplit("/", 1)[-1], []).append(orjson.loads(payload))
    assert set(seen) == {"connection", "factsheet", "state", "visualization"}
    for topic, bodies in seen.items():
        for body in bodies:
            validated(topic, body, version)
    assert seen["connection"][0]["connectionState"] == "ONLINE"
    sheet = seen["factsheet"][0]
    assert sheet["physicalParameters"]["speedMax"] == runtime.profile.limits.max_linear_velocity
    assert {"cancelOrder", "startPause", "stopPause", "initPosition", "stateRequest",
            "factsheetRequest", "startCharging", "stopCharging"} == {
        a["actionType"] for a in sheet["protocolFeatures"]["agvActions"]}
    state = seen["state"][-1]
    position = state["agvPosition"]
    assert position["mapId"] == "floor1" and 0.0 <= position["localizationScore"] <= 1.0
    assert state["batteryState"]["batteryCharge"] > 0 and state["operatingMode"] == "AUTOMATIC"
    visual = seen["visualization"]
    assert [v["headerId"] for v in visual] == sorted({v["headerId"] for v in visual})

    # A clean exit says OFFLINE, retained: a subscriber arriving later reads it.
    vehicle.close()
    later = subprocess.run(
        [mosquitto_binary("mosquitto_sub"), "-h", "127.0.0.1", "-p", str(broker.port),
         "-t", f"{BASE}/connection", "-C", "1", "-W", "5"],
        capture_output=True, text=True, timeout=10.0, check=True)
    assert validated("connection", orjson.loads(later.stdout), version)[
        "connectionState"] == "OFFLINE"


def test_an_order_from_the_master_drives_the_robot_across_two_nodes_and_once_only(
        vehicle: LoneVehicle, master: Master, runtime: RobotRuntime, version: str) -> None:
    vehicle.agent.publish_state(runtime.now())
    assert run_until(runtime, lambda: bool(master.of("state")), 5.0)
    here = master.last_state()["agvPosition"]
    order = master.order("o1", [("start", here["x"], here["y"]), ("lobby", 5.5, 12.5),
                                ("desk", 5.0, 6.0)])
    master.publish("order", order)

    def arrived() -> bool:
        states = master.of("state")
        return bool(states) and states[-1]["lastNodeId"] == "desk" and not states[-1]["driving"]

    assert run_until(runtime, arrived, 120.0)
    states = master.of("state")
    for state in states:
        validated("state", state, version)
    assert [s["headerId"] for s in states] == list(range(states[0]["headerId"],
                                                         states[0]["headerId"] + len(states)))
    passed = [s["lastNodeId"] for s in states if s["orderId"] == "o1"]
    assert [n for k, n in enumerate(passed) if k == 0 or n != passed[k - 1]] == [
        "start", "lobby", "desk"]
    final = states[-1]
    assert (final["nodeStates"], final["edgeStates"], final["errors"]) == ([], [], [])
    assert final["lastNodeSequenceId"] == 4
    during = next(s for s in states if s["orderId"] == "o1" and s["lastNodeId"] == "start")
    assert [n["nodeId"] for n in during["nodeStates"]] == ["lobby", "desk"]
    assert [e["edgeId"] for e in during["edgeStates"]] == ["e0", "e2"]
    pose = runtime.simulation.true_pose
    assert abs(pose.x - 5.0) < 0.3 and abs(pose.y - 6.0) < 0.3

    # The same order again (same orderId and orderUpdateId) is ignored: its first node is far
    # from the robot now, so taken again it would be rejected; ignored, nothing changes.
    master.publish("order", {**order, "headerId": 99})
    count = len(master.of("state"))
    master.instant("ask", "stateRequest")
    assert run_until(runtime, lambda: any(
        a["actionId"] == "ask" for s in master.of("state")[count:] for a in s["actionStates"]),
        5.0)
    last = master.last_state()
    assert (last["orderId"], last["lastNodeId"], last["errors"]) == ("o1", "desk", [])


def _errors(master: Master) -> list[tuple[str, str]]:
    seen: list[tuple[str, str]] = []
    for state in master.of("state"):
        for error in state["errors"]:
            item = (error["errorType"], error.get("errorDescription", ""))
            if item not in seen:
                seen.append(item)
    return seen


def test_bad_orders_are_rejected_with_the_standards_errors_never_a_crash(
        vehicle: LoneVehicle, master: Master, runtime: RobotRuntime, version: str) -> None:
    vehicle.agent.publish_state(runtime.now())
    assert run_until(runtime, lambda: bool(master.of("state")), 5.0)
    here = master.last_state()["agvPosition"]
    start = ("start", here["x"], here["y"])
    cases: list[tuple[dict[str, Any] | bytes, str, str]] = [
        (b"{not json", "validationError", "not JSON"),
        ({k: v for k, v in master.order("o2", [start, ("a", 5.5, 12.5)]).items()
          if k != "edges"}, "validationError", "$.edges"),
        (master.order("o3", [start, ("a", 5.5, 12.5)], map_id="floor9"), "validationError",
         "map 'floor9'"),
        (master.order("o4", [("far", 30.0, 20.0), ("a", 5.5, 12.5)]), "noRouteError",
         "from the vehicle"),
    ]
    for body, kind, words in cases:
        master.publish("order", body)
        assert run_until(runtime, lambda k=kind, w=words: any(  # type: ignore[misc]
            t == k and w in d for t, d in _errors(master)), 5.0), (kind, _errors(master))
    assert runtime.status().navigation_state == "idle"

    # A good order runs; an older update of it is stale.
    master.publish("order", master.order("o5", [start, ("b", 8.0, 11.0)], update=3))
    assert run_until(runtime, lambda: master.last_state()["orderId"] == "o5", 5.0)
    assert master.last_state()["errors"] == []
    master.publish("order", master.order("o5", [start, ("b", 8.0, 11.0)], update=1))
    assert run_until(runtime, lambda: any(t == "orderUpdateError" for t, _ in _errors(master)),
                     5.0)
    last = master.last_state()
    assert (last["orderId"], last["orderUpdateId"]) == ("o5", 3)
    for state in master.of("state"):
        validated("state", state, version)


def test_instant_actions_pause_resume_report_and_cancel_with_their_action_states(
        vehicle: LoneVehicle, master: Master, runtime: RobotRuntime, version: str) -> None:
    vehicle.agent.publish_state(runtime.now())
    assert run_until(runtime, lambda: bool(master.of("state")), 5.0)
    here = master.last_state()["agvPosition"]
    master.publish("order", master.order("o1", [("start", here["x"], here["y"]),
                                                 ("kitchen", 31.6, 21.0)]))
    assert run_until(runtime, lambda: master.last_state()["driving"], 20.0)

    def action(action_id: str) -> dict[str, Any] | None:
        for state in reversed(master.of("state")):
            for a in state["actionStates"]:
                if a["actionId"] == action_id:
                    return dict(a)
        return None

    master.instant("p1", "startPause")
    assert run_until(runtime, lambda: action("p1") is not None, 5.0)
    assert action("p1") == {"actionId": "p1", "actionType": "startPause",
                            "actionStatus": "FINISHED"}
    assert run_until(runtime, lambda: master.last_state()["paused"]
                     and not master.last_state()["driving"], 5.0)
    parked = runtime.simulation.true_pose
    runtime.advance(3.0)
    assert runtime.simulation.true_pose.distance_to(parked) < 0.05  # paused: it stays

    master.instant("p2", "stopPause")
    assert run_until(runtime, lambda: action("p2") is not None
                     and master.last_state()["driving"], 10.0)
    assert not master.last_state()["paused"]

    sheets = len(master.of("factsheet"))
    master.instant("f1", "factsheetRequest")
    assert run_until(runtime, lambda: len(master.of("factsheet")) > sheets, 5.0)
    validated("factsheet", master.of("factsheet")[-1], version)

    master.instant("c1", "cancelOrder")
    assert run_until(runtime, lambda: action("c1") is not None
                     and not master.last_state()["driving"], 10.0)
    assert action("c1") is not None and action("c1")["actionStatus"] == "FINISHED"  # type: ignore[index]
    assert master.last_state()["nodeStates"] == []
    master.instant("c2", "cancelOrder")  # nothing left to cancel
    assert run_until(runtime, lambda: action("c2") is not None, 5.0)
    failed = action("c2")
    assert failed is not None and failed["actionStatus"] == "FAILED"
    assert "noOrderToCancel" in [t for t, _ in _errors(master)]

    master.instant("x1", "teleport")
    assert run_until(runtime, lambda: action("x1") is not None, 5.0)
    unknown = action("x1")
    assert unknown is not None and unknown["actionStatus"] == "FAILED"
    assert "not supported" in unknown["resultDescription"]
    for state in master.of("state"):
        validated("state", state, version)


def test_a_horizon_waits_for_its_update_which_is_stitched_on_and_driven(
        vehicle: LoneVehicle, master: Master, runtime: RobotRuntime, version: str) -> None:
    vehicle.agent.publish_state(runtime.now())
    assert run_until(runtime, lambda: bool(master.of("state")), 5.0)
    here = master.last_state()["agvPosition"]
    nodes = [("start", here["x"], here["y"]), ("lobby", 5.5, 12.5), ("desk", 5.0, 6.0)]
    master.publish("order", master.order("o1", nodes, released=2))  # desk: the horizon

    def at_lobby() -> bool:
        state = master.last_state()
        return state["lastNodeId"] == "lobby" and not state["driving"]

    assert run_until(runtime, at_lobby, 90.0)
    runtime.advance(3.0)  # it waits there for the horizon to be released
    assert runtime.simulation.true_pose.distance_to(
        runtime.store.point("floor1", "lobby").pose) < 0.3
    waiting = master.last_state()
    assert [(n["nodeId"], n["released"]) for n in waiting["nodeStates"]] == [("desk", False)]
    assert [(e["edgeId"], e["released"]) for e in waiting["edgeStates"]] == [("e2", False)]

    # An update that does not start at the last released node cannot be stitched on.
    master.publish("order", master.order("o1", nodes[1:], update=1, first_sequence=4))
    assert run_until(runtime, lambda: any(
        t == "orderUpdateError" for t, _ in _errors(master)), 5.0)
    # The right one: from lobby (sequence 2), desk released.
    master.publish("order", master.order("o1", nodes[1:], update=2, first_sequence=2))

    def at_desk() -> bool:
        state = master.last_state()
        return state["lastNodeId"] == "desk" and not state["driving"]

    assert run_until(runtime, at_desk, 90.0)
    final = master.last_state()
    assert (final["orderUpdateId"], final["lastNodeSequenceId"], final["nodeStates"],
            final["errors"]) == (2, 4, [], [])
    for state in master.of("state"):
        validated("state", state, version)


def test_init_position_puts_the_robot_on_a_map_and_start_stop_charging_say_what_is_true(
        broker: Mosquitto, runtime: RobotRuntime, master: Master, version: str) -> None:
    # Not navigating yet: the master places the robot with initPosition, as the standard does.
    lone = LoneVehicle(runtime, "r1", VehicleConfig(broker.url, version=version))
    try:
        master.instant("i1", "initPosition", [
            {"key": "x", "value": 8.0}, {"key": "y", "value": 8.5},
            {"key": "theta", "value": 0.0}, {"key": "mapId", "value": "floor1"}])

        def status_of(action_id: str) -> str | None:
            for state in reversed(master.of("state")):
                for a in state["actionStates"]:
                    if a["actionId"] == action_id:
                        return str(a["actionStatus"])
            return None

        assert run_until(runtime, lambda: status_of("i1") is not None, 5.0)
        assert status_of("i1") == "FINISHED"
        assert runtime.status().map == "floor1"
        master.instant("i2", "initPosition", [{"key": "x", "value": "eight"}])
        master.instant("s1", "startCharging")  # not on a charger
        master.instant("s2", "stopCharging")  # not charging: already true
        assert run_until(runtime, lambda: None not in (
            status_of("i2"), status_of("s1"), status_of("s2")), 5.0)
        assert (status_of("i2"), status_of("s1"), status_of("s2")) == (
            "FAILED", "FAILED", "FINISHED")
        assert master.last_state()["agvPosition"]["mapId"] == "floor1"
    finally:
        lone.close()
