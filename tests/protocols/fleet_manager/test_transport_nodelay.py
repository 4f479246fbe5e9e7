"""The fleet's MQTT connections send each packet at once (``TCP_NODELAY``): with Nagle's
algorithm a small order or state written while an earlier packet is unacknowledged waited for
the broker's delayed ACK (~40 ms on Linux), the order latency's median at 1,000 vehicles."""

from __future__ import annotations

import socket
import time

from polynav.fleet.mqtt_transport import MqttTransport
from tests.helpers.mosquitto import Mosquitto


def test_an_mqtt_transport_socket_has_nodelay_and_keeps_it_after_a_reconnection(
        broker: Mosquitto) -> None:
    with MqttTransport(broker.url, "nodelay", reconnect_delay=(1, 1)) as transport:
        def nodelay() -> int:
            sock = transport._client.socket()
            assert sock is not None
            return int(sock.getsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY))

        assert transport.wait_connected(10.0)
        assert nodelay() == 1
        broker.restart()
        deadline = time.monotonic() + 20.0
        while transport.stats().connects < 2 and time.monotonic() < deadline:
            time.sleep(0.05)
        assert transport.stats().connects == 2 and transport.wait_connected(20.0)
        assert nodelay() == 1  # the new socket too
