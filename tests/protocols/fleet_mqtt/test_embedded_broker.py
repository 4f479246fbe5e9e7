"""``polynav run --broker embedded``: an MQTT broker inside the process (issue #36 item 4),
watched with Debian's real ``mosquitto_sub`` and used by paho exactly as any broker."""

from __future__ import annotations

import socket
import subprocess
import threading
import time
from pathlib import Path
from typing import Any

import orjson
import paho.mqtt.client as paho
import pytest
from paho.mqtt.enums import CallbackAPIVersion

from polynav.fleet.vda5050 import validation
from polynav.house.broker import BrokerStartError, EmbeddedBroker
from tests.helpers.mosquitto import free_loopback_port, mosquitto_binary
from tests.helpers.polynav_run import running, stop_run

WAIT = 10.0


def _client(port: int, client_id: str, got: list[tuple[str, bytes, bool]],
            will: tuple[str, bytes] | None = None) -> paho.Client:
    client = paho.Client(CallbackAPIVersion.VERSION2, client_id=client_id,
                         protocol=paho.MQTTv311)
    if will is not None:
        client.will_set(will[0], will[1], 1, True)
    connected = threading.Event()
    client.on_connect = lambda *args: connected.set()
    client.on_message = lambda c, u, msg: got.append((msg.topic, bytes(msg.payload),
                                                      bool(msg.retain)))
    client.connect("127.0.0.1", port)
    client.loop_start()
    assert connected.wait(WAIT)
    return client


def _wait(done: Any, timeout: float = WAIT) -> bool:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if done():
            return True
        time.sleep(0.02)
    return bool(done())


def test_the_embedded_broker_carries_retained_messages_and_last_wills_for_paho() -> None:
    with EmbeddedBroker(0) as broker:
        assert broker.port > 0 and broker.url == f"mqtt://127.0.0.1:{broker.port}"
        watcher_got: list[tuple[str, bytes, bool]] = []
        vehicle = _client(broker.port, "vehicle", [], will=("v/connection", b"BROKEN"))
        vehicle.publish("v/connection", b"ONLINE", 1, True).wait_for_publish(WAIT)
        watcher = _client(broker.port, "watcher", watcher_got)
        watcher.subscribe("v/#", 1)
        assert _wait(lambda: ("v/connection", b"ONLINE", True) in watcher_got)
        vehicle.publish("v/state", b"{}", 0)
        assert _wait(lambda: ("v/state", b"{}", False) in watcher_got)
        # The vehicle vanishes without DISCONNECT: the broker publishes its will.
        sock = vehicle.socket()
        assert isinstance(sock, socket.socket)
        sock.shutdown(socket.SHUT_RDWR)
        assert _wait(lambda: any(t == "v/connection" and p == b"BROKEN"
                                 for t, p, _ in watcher_got))
        vehicle.loop_stop()
        watcher.disconnect()
        watcher.loop_stop()


def test_a_taken_port_is_a_clear_error() -> None:
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        with pytest.raises(BrokerStartError, match=f"127.0.0.1:{port}"):
            EmbeddedBroker(port)


def test_polynav_run_with_the_embedded_broker_on_a_taken_port_exits_1(tmp_path: Path) -> None:
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = str(taken.getsockname()[1])
        with running(tmp_path, None, "--broker", "embedded", "--broker-port", port) as (proc,
                                                                                     _):
            _, err = proc.communicate(timeout=60)
    assert proc.returncode == 1
    assert "cannot start the embedded MQTT broker on 127.0.0.1:" + port in err
    assert len(err.strip().splitlines()) == 1, err


def test_polynav_run_robots_3_on_the_embedded_broker_shows_valid_vda5050_traffic(
        tmp_path: Path) -> None:
    port = free_loopback_port()
    with running(tmp_path, None, "--robots", "3", "--broker", "embedded", "--broker-port",
                 str(port), "--vda-version", "2.1.0") as (proc, lines):
        url = f"mqtt://127.0.0.1:{port}"
        assert any(f"embedded MQTT broker on {url}" in line for line in lines), lines
        assert any(f"vehicles on {url}" in line for line in lines), lines
        # What a user types to watch it: every robot's connection and factsheet (retained),
        # then states (at least every second in a building) and visualization (1 Hz).
        watched = subprocess.run(
            [mosquitto_binary("mosquitto_sub"), "-h", "127.0.0.1", "-p", str(port),
             "-t", "uagv/v2/#", "-v", "-W", "4"],
            capture_output=True, text=True, timeout=20.0, check=False)
        stop_run(proc, [line for line in lines if "robot1 " in line or "Ctrl-C" in line])
    seen: dict[tuple[str, str], int] = {}
    for line in watched.stdout.splitlines():
        topic, _, payload = line.partition(" ")
        _, _, manufacturer, serial, kind = topic.split("/")
        body = orjson.loads(payload)
        validation.validate(kind, "2.1.0", body)
        assert (body["manufacturer"], body["serialNumber"], body["version"]) == (
            manufacturer, serial, "2.1.0")
        seen[(serial, kind)] = seen.get((serial, kind), 0) + 1
    for serial in ("robot1", "robot2", "robot3"):
        for kind in ("connection", "factsheet", "state", "visualization"):
            assert seen.get((serial, kind), 0) >= 1, (serial, kind, sorted(seen))
        assert seen[(serial, "state")] >= 2
