"""The broker goes away mid-mission (issue #36 item 1): a real Mosquitto is stopped while two
robots of a building drive their orders through a shared corridor, and started again on the
same port. The robots drive on meanwhile, reconnect with backoff, say ONLINE again, ask again
for the zones they need, and finish their orders; the master control hears how they ended."""

from __future__ import annotations

import logging
import subprocess
import threading
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import orjson
import paho.mqtt.client as paho
import pytest
from paho.mqtt.enums import CallbackAPIVersion

from polynav.fleet.mqtt_transport import MqttTransport
from polynav.fleet.vda5050 import validation
from polynav.fleet.vehicle import LoneVehicle, VehicleConfig
from polynav.house.building import Building
from polynav.runtime.config import RuntimeConfig
from polynav.runtime.robot_runtime import RobotRuntime
from polynav.store.site_store import SiteStore
from polynav.worlds.world import World
from tests.helpers.mosquitto import Mosquitto, free_loopback_port, mosquitto_binary
from tests.helpers.polynav_run import running
from tests.protocols.fleet_mqtt.conftest import WAIT


def retained(broker: Mosquitto, topic: str) -> dict[str, object]:
    got = subprocess.run(
        [mosquitto_binary("mosquitto_sub"), "-h", "127.0.0.1", "-p", str(broker.port),
         "-t", topic, "-C", "1", "-W", "10"],
        capture_output=True, text=True, timeout=15.0, check=True)
    body: dict[str, object] = orjson.loads(got.stdout)
    return body


def _paced(building: Building, seconds: float, sim_seconds: float) -> None:
    """Run the building at least ``seconds`` of wall time and ``sim_seconds`` of simulated
    time, 2 ms of wall time per control period (the network threads get their turn)."""
    deadline = time.monotonic() + seconds
    sim_deadline = building.now() + sim_seconds

    def over() -> bool:
        time.sleep(0.002)
        return time.monotonic() >= deadline and building.now() >= sim_deadline

    building.advance_until(over, timeout=3600.0)


def test_a_broker_restarted_mid_mission_costs_no_order(
        broker: Mosquitto, world: World, store: SiteStore,
        caplog: pytest.LogCaptureFixture) -> None:
    caplog.set_level(logging.INFO, logger="polynav.fleet")
    building = Building(store, world, robots=2, config=RuntimeConfig(people=False),
                        vehicles=VehicleConfig(broker.url, version="2.1.0",
                                               visualization_period=None))
    try:
        orders = {"robot1": building.send("robot1", "office_3", "floor1"),
                  "robot2": building.send("robot2", "office_1", "floor1")}

        def driving() -> bool:
            time.sleep(0.002)
            return all(building.master.state(s) is not None and building.master.state(s).driving
                       for s in orders)  # type: ignore[union-attr]

        assert building.advance_until(driving, timeout=20.0)
        before = {s: building.master.state(s) for s in orders}
        poses = {s: building.agent(s).runtime.status().pose for s in orders}

        broker.stop()
        links = [link.transport for link in building.links]
        assert all(t.wait_disconnected(WAIT) for t in links)
        _paced(building, 2.5, 15.0)  # the robots drive on; each reconnection attempt fails
        moved = {s: building.agent(s).runtime.status().pose.distance_to(poses[s])
                 for s in orders}
        assert all(d > 0.5 for d in moved.values()), moved
        # One has come to the corridor meanwhile: it asked for it, unheard, and waits short
        # of it (asked again once the broker is back, it is granted and goes on).
        assert any(building.agent(s).traffic.waiting_for for s in orders)
        broker.restart()  # same port; it has forgotten every retained message
        # Reconnecting takes wall time (the backoff); the simulation waits for it rather than
        # racing through its timeout on a loaded machine.
        _paced(building, 1.0, 5.0)
        assert all(t.wait_connected(WAIT) for t in building.mqtt_clients)

        def done() -> bool:
            time.sleep(0.002)
            return all(building.outcome(s, o) is not None for s, o in orders.items()) and all(
                (st := building.master.state(s)) is not None and st.order_id == orders[s]
                and not st.node_states for s in orders)

        assert building.advance_until(done, timeout=300.0)
        assert {s: building.outcome(s, o) for s, o in orders.items()} == {
            "robot1": "succeeded", "robot2": "succeeded"}
        after = {s: building.master.state(s) for s in orders}
        for serial in orders:
            first, last = before[serial], after[serial]
            assert first is not None and last is not None
            assert last.header.header_id > first.header.header_id  # one count, never reset
            assert last.errors == ()
        entries = {e.robot_id: e for e in building.entries()}
        assert {s: entries[s].order_state for s in orders} == {
            "robot1": "succeeded", "robot2": "succeeded"}
        assert all(t.stats().connects == 2 for t in [*links, building.transport]
                   if isinstance(t, MqttTransport))
        # The restarted broker has the robots' connection and factsheet again (retained).
        for serial in orders:
            online = retained(broker, f"uagv/v2/polynav/{serial}/connection")
            validation.validate("connection", "2.1.0", online)
            assert online["connectionState"] == "ONLINE"
            validation.validate("factsheet", "2.1.0",
                                retained(broker, f"uagv/v2/polynav/{serial}/factsheet"))
    finally:
        building.close()
    said = caplog.text
    assert "lost the broker" in said
    assert "still unreachable (attempt 1); next attempt in 2 s" in said
    assert "reconnected to " + broker.url in said
    assert "back on the broker" in said


def test_a_transport_says_each_failed_attempt_and_its_backoff_then_reconnects(
        broker: Mosquitto, tmp_path: Path, caplog: pytest.LogCaptureFixture) -> None:
    caplog.set_level(logging.INFO, logger="polynav.fleet.mqtt_transport")
    back: list[int] = []
    with MqttTransport(broker.url, "watcher", reconnect_delay=(1, 2)) as transport:
        transport.add_reconnect_listener(lambda: back.append(transport.stats().connects))
        inbox = transport.subscribe_raw("a/+/state")
        assert transport.wait_subscribed(WAIT)
        broker.stop()
        assert transport.wait_disconnected(WAIT)
        time.sleep(3.6)  # attempts after 1 s and then every 2 s (the longest wait)
        attempts = [r.getMessage() for r in caplog.records if "still unreachable" in
                    r.getMessage()]
        assert attempts[:2] == [
            f"MQTT client watcher: broker at {broker.url} still unreachable (attempt 1); "
            "next attempt in 2 s",
            f"MQTT client watcher: broker at {broker.url} still unreachable (attempt 2); "
            "next attempt in 2 s"]
        # Meanwhile a QoS 0 message cannot go: counted, and said once for the outage.
        transport.publish_raw("a/r1/visualization", b"{}")
        transport.publish_raw("a/r1/visualization", b"{}")
        assert transport.stats().unsent == 2
        assert sum("not sent" in r.getMessage() for r in caplog.records) == 1
        broker.restart()
        assert transport.wait_subscribed(WAIT)  # subscribed again on the new broker
        deadline = time.monotonic() + WAIT
        while not back and time.monotonic() < deadline:
            time.sleep(0.01)
        assert back == [2]
        with MqttTransport(broker.url, "robot") as robot:
            robot.publish_raw("a/r1/state", b"{}")
            deadline = time.monotonic() + WAIT
            while not (got := inbox.drain()) and time.monotonic() < deadline:
                time.sleep(0.01)
        assert [m.payload for m in got] == [b"{}"]


def test_a_building_with_an_unreachable_broker_at_start_up_says_so_in_one_line_and_exits_1(
        tmp_path: Path) -> None:
    # (A lone robot's: test_run_broker.py.)
    url = f"mqtt://127.0.0.1:{free_loopback_port()}"  # nothing listens there
    with running(tmp_path, None, "--robots", "2", "--broker", url,
                 "--connect-timeout", "1.5") as (proc, _):
        _, err = proc.communicate(timeout=90)
    assert proc.returncode == 1
    assert err.strip().splitlines() == [
        f"polynav run: MQTT broker at {url} not reachable after 1.5 s: "
        "ConnectionRefusedError: [Errno 111] Connection refused"], err


class Watcher:
    """A foreign master's view: every message under the robot's topics, subscribed again
    whenever its own client reconnects (paho, nothing of polynav's)."""

    def __init__(self, port: int, base: str) -> None:
        self.base = base
        self.seen: list[tuple[str, dict[str, Any]]] = []
        self._lock = threading.Lock()
        self.client = paho.Client(CallbackAPIVersion.VERSION2, client_id="watcher",
                                  protocol=paho.MQTTv311)
        self.client.reconnect_delay_set(1, 1)
        self.client.on_connect = lambda c, *args: c.subscribe(f"{base}/#", qos=1)
        self.client.on_message = self._on_message
        self.client.connect("127.0.0.1", port)
        self.client.loop_start()

    def _on_message(self, client: paho.Client, userdata: Any, msg: paho.MQTTMessage) -> None:
        kind = msg.topic.rsplit("/", 1)[-1]
        if kind in ("order", "instantActions"):
            return
        with self._lock:
            self.seen.append((kind, orjson.loads(msg.payload)))

    def of(self, kind: str) -> list[dict[str, Any]]:
        with self._lock:
            return [body for k, body in self.seen if k == kind]

    def publish(self, kind: str, body: dict[str, Any]) -> None:
        self.client.publish(f"{self.base}/{kind}", orjson.dumps(body), qos=0).wait_for_publish(
            WAIT)

    def close(self) -> None:
        self.client.disconnect()
        self.client.loop_stop()


def test_a_lone_vehicle_finishes_its_order_offline_and_says_so_when_the_broker_is_back(
        broker: Mosquitto, world: World, store: SiteStore) -> None:
    runtime = RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False))
    runtime.start_navigation("floor1")
    vehicle = LoneVehicle(runtime, "r1", VehicleConfig(broker.url, visualization_period=None))
    watcher = Watcher(broker.port, "uagv/v2/polynav/r1")

    def run_until(done: Callable[[], bool], wall: float = 15.0) -> bool:
        deadline = time.monotonic() + wall
        while not done():
            if time.monotonic() > deadline:
                return False
            runtime.advance(0.1)
            time.sleep(0.002)
        return True

    try:
        vehicle.agent.publish_state(runtime.now())
        assert run_until(lambda: bool(watcher.of("state")))
        here = watcher.of("state")[-1]["agvPosition"]
        watcher.publish("order", {
            "headerId": 1, "timestamp": "2026-11-28T12:00:00.000Z", "version": "2.0.0",
            "manufacturer": "polynav", "serialNumber": "r1", "orderId": "o1",
            "orderUpdateId": 0, "edges": [{"edgeId": "e0", "sequenceId": 1, "released": True,
                                           "startNodeId": "start", "endNodeId": "lobby",
                                           "actions": []}],
            "nodes": [{"nodeId": "start", "sequenceId": 0, "released": True, "actions": [],
                       "nodePosition": {"x": here["x"], "y": here["y"], "mapId": "floor1"}},
                      {"nodeId": "lobby", "sequenceId": 2, "released": True, "actions": [],
                       "nodePosition": {"x": 5.5, "y": 12.5, "mapId": "floor1"}}]})
        assert run_until(lambda: any(s["driving"] for s in watcher.of("state")))
        before = max(s["headerId"] for s in watcher.of("state"))

        said = max(c["headerId"] for c in watcher.of("connection"))
        broker.stop()
        assert vehicle.link.transport.wait_disconnected(WAIT)
        # Offline, it drives on to the end of its released nodes.
        assert run_until(lambda: vehicle.agent.outcome == "succeeded", wall=20.0)
        broker.restart()
        # Back: it says ONLINE again (the new broker has no retained message of it; the old
        # one may have published the will, CONNECTIONBROKEN, as it stopped).
        assert vehicle.link.transport.wait_connected(WAIT)

        def online_again() -> bool:
            return any(c["headerId"] > said and c["connectionState"] == "ONLINE"
                       for c in watcher.of("connection"))

        deadline = time.monotonic() + WAIT
        while not online_again() and time.monotonic() < deadline:
            time.sleep(0.01)
        assert online_again(), watcher.of("connection")
        back = runtime.now()

        def told() -> bool:
            states = [s for s in watcher.of("state") if s["headerId"] > before]
            return bool(states) and states[-1]["lastNodeId"] == "lobby" and (
                states[-1]["nodeStates"] == [] and not states[-1]["driving"])

        assert run_until(told, wall=20.0)
        assert runtime.now() - back < 5.0  # at once, not at the next 30 s state
        final = watcher.of("state")[-1]
        validation.validate("state", "2.0.0", final)
        assert (final["orderId"], final["lastNodeSequenceId"], final["errors"]) == ("o1", 2, [])
        assert vehicle.link.transport.stats().connects == 2
    finally:
        watcher.close()
        vehicle.close()
