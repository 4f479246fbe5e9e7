"""Many vehicles, or one master control over many, on one MQTT connection.

A process that runs hundreds of light vehicles (:mod:`polynav.fleet.kinematic_vehicle`), or a
master control over hundreds of robots, would otherwise hold two subscriptions per robot, and
the MQTT client matches every message against every subscription (thousands of filter checks
per message). :class:`SharedClient` subscribes once per message kind with a wildcard
(``uagv/v2/<manufacturer>/+/<kind>``) and hands each message to the inbox of its serial
number's exact topic, decoding only those someone here listens to (a worker hears every
vehicle's orders; it decodes its own).

It is a :class:`~polynav.fleet.interface.Transport`: the vehicles or the master control use it
as they use a transport of their own. A subscription with ``+`` for the serial number
(``uagv/v2/<manufacturer>/+/connection``, the fleet manager's) gets every vehicle's messages
of that kind. What it cannot give each vehicle is a last will of its
own (MQTT has one will per connection): a vehicle sharing a connection says OFFLINE when it
closes, but if the process dies no CONNECTIONBROKEN is published for it.

``observer``, if given, is called with every message handed over (serial number, kind, the
message, the wall time it was read at): the benchmark's order latency and headerId gaps.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Protocol

from polynav.errors import InvalidRequest
from polynav.fleet import codec
from polynav.fleet import messages as m
from polynav.fleet.mqtt_transport import MqttTransport, RawInbox

Observer = Callable[[str, str, m.Received, float], None]


class _Pump(Protocol):
    auto_pump: bool

    def pump(self) -> None: ...


class LocalInbox:
    """One exact topic's messages, filled by :meth:`SharedClient.pump`."""

    def __init__(self, client: _Pump) -> None:
        self._client = client
        self.items: list[tuple[str, m.Received]] = []

    def drain(self) -> list[m.Received]:
        """The messages since the last drain, oldest first (reads the connection first, unless
        the client is pumped by its owner)."""
        return [item for _, item in self.drain_topics()]

    def drain_topics(self) -> list[tuple[str, m.Received]]:
        """As :meth:`drain`, each message with the topic it arrived on."""
        if self._client.auto_pump:
            self._client.pump()
        items, self.items = self.items, []
        return items


class SharedClient:
    """Exact-topic inboxes over one wildcard subscription per kind (see the module docstring).

    Args:
        mqtt: the connection.
        manufacturer: the third level of the topics.
        observer: told of every message handed over.
        auto_pump: whether each inbox's drain reads the connection first; False: only
            :meth:`pump` does, so an owner that pumps once and then drains every inbox (a
            master control's tick) sees in its inboxes exactly what its observer saw.
    """

    def __init__(self, mqtt: MqttTransport, manufacturer: str = m.DEFAULT_MANUFACTURER, *,
                 observer: Observer | None = None, auto_pump: bool = True) -> None:
        self.mqtt = mqtt
        self.auto_pump = auto_pump
        self.manufacturer = manufacturer
        self._observer = observer
        self._raw: dict[str, RawInbox] = {}
        self._local: dict[tuple[str, str], LocalInbox] = {}
        self._touched: set[str] = set()
        self.ignored = 0

    def publish(self, topic: str, message: m.Message) -> None:
        """Publish ``message`` on ``topic`` (the connection's QoS and retain for its kind)."""
        self.mqtt.publish(topic, message)

    def subscribe(self, topic: str) -> LocalInbox:
        """An inbox for ``topic``, ``uagv/v2/<manufacturer>/<serial>/<kind>``, ``serial``
        exactly or ``+`` for every vehicle's.

        Raises:
            InvalidRequest: another topic shape or manufacturer, or other wildcards.
        """
        serial, kind = self._split(topic)
        if (serial is None or kind is None or "#" in topic or "+" in kind
                or ("+" in serial and serial != "+")):
            raise InvalidRequest("topic", f"{topic!r}: not a vehicle topic of "
                                          f"{self.manufacturer}")
        if kind not in self._raw:
            self._raw[kind] = self.mqtt.subscribe_raw(
                m.topic("+", kind, self.manufacturer))
        inbox = self._local.get((serial, kind))
        if inbox is None:
            inbox = self._local[(serial, kind)] = LocalInbox(self)
        return inbox

    def wait(self, kind: str, timeout: float) -> bool:
        """Block until a message of ``kind`` is waiting, up to ``timeout`` [s]."""
        raw = self._raw.get(kind)
        if raw is None:
            time.sleep(timeout)
            return False
        return raw.wait(timeout)

    def pump(self) -> None:
        """Hand what arrived to the inboxes of the serial numbers listened to here."""
        for kind, raw in self._raw.items():
            messages = raw.drain()
            if not messages:
                continue
            now = time.monotonic()
            every = self._local.get(("+", kind))
            for message in messages:
                serial, _ = self._split(message.topic)
                inbox = self._local.get((serial or "", kind))
                if inbox is None and every is None:
                    self.ignored += 1
                    continue
                item = codec.read(kind, message.payload)
                if self._observer is not None:
                    self._observer(serial or "", kind, item, now)
                if inbox is not None:
                    inbox.items.append((message.topic, item))
                    self._touched.add(serial or "")
                if every is not None:
                    every.items.append((message.topic, item))

    def take_touched(self) -> set[str]:
        """The serial numbers that messages were handed to since the last call: a process of
        many vehicles ticks those at once rather than all of them."""
        touched, self._touched = self._touched, set()
        return touched

    def _split(self, topic: str) -> tuple[str | None, str | None]:
        parts = topic.split("/")
        if len(parts) != 5 or parts[:3] != [m.INTERFACE, m.MAJOR, self.manufacturer]:
            return None, None
        return parts[3], parts[4]
