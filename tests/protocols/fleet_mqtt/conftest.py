"""A real Mosquitto broker on a loopback port for each test, and MQTT transports to it that
are closed when the test ends."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest

from polynav.fleet.mqtt_transport import MqttTransport
from tests.helpers.mosquitto import Mosquitto

WAIT = 10.0
"""The longest a test waits for the broker to deliver or a client to (re)connect [s]."""


@pytest.fixture
def broker(tmp_path: Path) -> Iterator[Mosquitto]:
    with Mosquitto(tmp_path) as running:
        yield running


TransportFactory = Callable[..., MqttTransport]


@pytest.fixture
def connect(broker: Mosquitto) -> Iterator[TransportFactory]:
    """``connect("client-id", **options)``: a transport to the test's broker."""
    opened: list[MqttTransport] = []

    def make(client_id: str, **options: Any) -> MqttTransport:
        transport = MqttTransport(broker.url, client_id, **options)
        opened.append(transport)
        return transport

    yield make
    for transport in opened:
        transport.close()
