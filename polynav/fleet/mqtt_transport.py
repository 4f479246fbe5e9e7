"""The fleet's messages over MQTT, through a real broker (DESIGN §9, VDA 5050 §6.2).

:class:`MqttTransport` is the :class:`~polynav.fleet.interface.Transport` for a fleet that spans
machines: the same topics and the same bytes as the in-process transport (every message goes
through :mod:`polynav.fleet.codec`), carried by an MQTT 3.1.1 broker such as Mosquitto. It runs
paho-mqtt's network loop on its own thread; what arrives is decoded there and queued per
subscription, and the fleet or the robot agent reads it with ``drain()`` on its own loop, as it
does with the in-process transport.

How each message travels follows VDA 5050 §6.2 and §6.14-6.15: ``connection`` at QoS 1 and
retained, ``factsheet`` retained at QoS 0, everything else (order, instantActions, state,
visualization, and polynav's zone requests and answers, which 3.0 sends at QoS 0 too) at QoS 0,
not retained (:data:`DELIVERY`).

The connection is kept: when the broker goes away the loop reconnects with exponential backoff
(each failed attempt a log line with the wait before the next) and subscribes again to every
topic it had; listeners added with :meth:`MqttTransport.add_reconnect_listener` are then told,
so a vehicle can say ONLINE again and publish its state (a restarted broker has forgotten its
retained messages, and QoS 0 messages published meanwhile were lost). While the broker is away
a QoS 0 message cannot be sent: it is counted as unsent, and logged once per outage. A broker
that cannot be reached at start-up is an error (:class:`BrokerUnreachable`) after a bounded
wait, so a misconfigured robot says so instead of waiting for ever.

A message that does not decode (not JSON, a field missing or of the wrong type, a breach of the
VDA 5050 schema, more than :data:`MAX_MESSAGE` bytes) is logged and counted as dropped: one bad
publisher must not stop a robot from hearing the fleet. A fleet-message subscription hands it
over as a :class:`~polynav.fleet.messages.Rejected` (so a vehicle can answer it with a
validationError in its state); a raw subscription leaves it out.

Messages the codec does not cover (``connection``, ``factsheet``, ``visualization`` in their
VDA form) go through :meth:`MqttTransport.publish_raw` and :meth:`MqttTransport.subscribe_raw`.

A client that closes while messages are still arriving for it may, rarely, have its socket
reset by the kernel instead of closed, and the broker then publishes its will.

Overlapping subscriptions (``a/+/state`` and ``a/r1/state``) may make the broker deliver a
message once per subscription; keep one subscription per topic pattern.
"""

from __future__ import annotations

import contextlib
import logging
import socket
import threading
import time
import urllib.parse
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from types import TracebackType
from typing import Any, Generic, TypeVar

import orjson
import paho.mqtt.client as paho
from paho.mqtt.enums import CallbackAPIVersion, MQTTErrorCode
from paho.mqtt.properties import Properties
from paho.mqtt.reasoncodes import ReasonCode

from polynav.errors import ConfigError, InvalidRequest, PolynavError
from polynav.fleet import codec
from polynav.fleet.messages import Message, Received, Rejected
from polynav.fleet.vda5050 import validation

log = logging.getLogger(__name__)
wire = logging.getLogger("polynav.fleet.wire")

T = TypeVar("T")


@dataclass(frozen=True, slots=True)
class Delivery:
    """How a message kind travels: MQTT QoS (0 at most once, 1 at least once) and retain."""

    qos: int
    retain: bool


DELIVERY: dict[str, Delivery] = {
    "connection": Delivery(qos=1, retain=True),
    "factsheet": Delivery(qos=0, retain=True),
}
"""QoS and retain by the topic's last level (VDA 5050 2.1 §6.2, §6.14, §6.15); others QoS 0."""

_DEFAULT_DELIVERY = Delivery(qos=0, retain=False)

MAX_MESSAGE = 512 * 1024
"""The longest message read [bytes] (the factsheet's ``maxStringLens.msgLen``): a 1000-node
order is about 220 kB; a longer message is refused before it is parsed, so one 2 MB payload
cannot hold the network thread for seconds of schema checks."""


def delivery(topic: str) -> Delivery:
    """How a message on ``topic`` travels, by its last level (``.../connection``)."""
    return DELIVERY.get(topic.rsplit("/", 1)[-1], _DEFAULT_DELIVERY)


class BrokerUnreachable(PolynavError):
    """The MQTT broker did not accept a connection within the wait allowed at start-up."""

    def __init__(self, url: str, waited: float, reason: str) -> None:
        super().__init__(f"MQTT broker at {url} not reachable after {waited:.1f} s: {reason}")
        self.url = url
        self.reason = reason


@dataclass(frozen=True, slots=True)
class RawMessage:
    """A message as it came off the broker: its topic, its bytes and how it travelled."""

    topic: str
    payload: bytes
    qos: int
    retain: bool


@dataclass(frozen=True, slots=True)
class TransportStats:
    """Counts since the transport started.

    Attributes:
        published: messages handed to the broker (or queued for it, at QoS 1 or 2).
        unsent: messages lost because the broker was not connected (QoS 0) or the queue was full.
        received: messages delivered to a subscription's inbox.
        dropped: messages received that did not decode or broke their schema.
        connects: successful connections to the broker, the first included.
    """

    published: int
    unsent: int
    received: int
    dropped: int
    connects: int


class _Queue(Generic[T]):
    """A subscription's queue, filled by the network thread and drained by the reader."""

    def __init__(self, topic_filter: str, max_message: int = MAX_MESSAGE) -> None:
        self.topic_filter = topic_filter
        self.max_message = max_message
        self.dropped = 0
        self._items: deque[tuple[str, T]] = deque()
        self._arrived = threading.Condition()

    def drain(self) -> list[T]:
        """What arrived since the last drain, oldest first."""
        return [item for _, item in self.drain_topics()]

    def drain_topics(self) -> list[tuple[str, T]]:
        """What arrived since the last drain, oldest first, each with the topic it came on
        (a wildcard subscription's reader learns the sender from it)."""
        with self._arrived:
            items = list(self._items)
            self._items.clear()
        return items

    def wait(self, timeout: float) -> bool:
        """Block until something is waiting to be drained, up to ``timeout`` [s]; True if so."""
        with self._arrived:
            return self._arrived.wait_for(lambda: bool(self._items), timeout)

    def offer(self, message: paho.MQTTMessage) -> bool:
        """Decode and queue ``message``; False (logged, counted) if it does not decode."""
        try:
            _check_size(message, self.max_message)
            item = self.read(message)
        except InvalidRequest as exc:
            self.dropped += 1
            log.warning("dropped a message on %s: %s", message.topic, str(exc)[:300])
            return False
        self._put(message.topic, item)
        return True

    def _put(self, topic: str, item: T) -> None:
        with self._arrived:
            self._items.append((topic, item))
            self._arrived.notify_all()

    def read(self, message: paho.MQTTMessage) -> T:
        raise NotImplementedError


class MessageInbox(_Queue[Received]):
    """A subscription to fleet messages (:mod:`polynav.fleet.messages`), decoded by the codec;
    the message kind is the last level of the topic it arrived on. A message that does not
    decode or breaks its schema is counted as dropped and handed over as a
    :class:`~polynav.fleet.messages.Rejected`, so a vehicle can report it in its state."""

    def offer(self, message: paho.MQTTMessage) -> bool:
        kind = message.topic.rsplit("/", 1)[-1]
        try:
            _check_size(message, self.max_message)
            item = self.read(message)
        except InvalidRequest as exc:
            item = Rejected(kind, exc.field, str(exc))
        except Exception as exc:  # a reader's bug: refused like bad input, and said loudly
            log.error("a message on %s could not be read", message.topic, exc_info=True)
            item = Rejected(kind, "message", f"could not be read: {type(exc).__name__}")
        if isinstance(item, Rejected):
            self.dropped += 1
            reason = item.reason if len(item.reason) <= 300 else item.reason[:300] + "..."
            log.warning("refused a message on %s: %s", message.topic, reason)
        self._put(message.topic, item)
        return not isinstance(item, Rejected)

    def read(self, message: paho.MQTTMessage) -> Received:
        return codec.read(message.topic.rsplit("/", 1)[-1], bytes(message.payload))


class RawInbox(_Queue[RawMessage]):
    """A subscription to messages as bytes; with ``version``, each must be JSON that passes the
    VDA 5050 schema of its topic's last level in that version (else it is dropped)."""

    def __init__(self, topic_filter: str, version: str | None) -> None:
        super().__init__(topic_filter)
        self.version = version

    def read(self, message: paho.MQTTMessage) -> RawMessage:
        if self.version is not None:
            try:
                parsed = orjson.loads(message.payload)
            except orjson.JSONDecodeError as exc:
                raise InvalidRequest("message", f"not JSON: {exc}") from None
            validation.validate(message.topic.rsplit("/", 1)[-1], self.version, parsed)
        return RawMessage(message.topic, bytes(message.payload), message.qos, bool(message.retain))


class MqttTransport:
    """Fleet messages over an MQTT broker (see the module docstring).

    Args:
        url: the broker, ``mqtt://host[:port]`` (port 1883 by default).
        client_id: this client's MQTT id, unique on the broker (a second client with the same
            id makes the broker drop the first).
        will: the last will (topic, payload, QoS, retain) the broker publishes if this client
            vanishes without disconnecting; VDA 5050 vehicles set their ``connection`` topic's
            CONNECTIONBROKEN message here.
        connect_timeout: how long to keep trying to reach the broker at start-up [s].
        keepalive: MQTT keep-alive [s]; a dead broker is noticed within about 1.5 times this.
        reconnect_delay: the first and the longest wait between reconnection attempts [s],
            doubling in between.
        max_queued: QoS 1 and 2 messages kept while the broker is away; more are lost.
        close_timeout: how long :meth:`close` waits for the broker to acknowledge the QoS 1
            and 2 messages still in flight [s].

    Raises:
        ConfigError: a URL that is not ``mqtt://host[:port]``, or a bad will.
        BrokerUnreachable: no broker accepted the connection within ``connect_timeout``.
    """

    def __init__(
        self,
        url: str,
        client_id: str,
        *,
        will: tuple[str, bytes, int, bool] | None = None,
        connect_timeout: float = 10.0,
        keepalive: int = 30,
        reconnect_delay: tuple[int, int] = (1, 30),
        max_queued: int = 1000,
        close_timeout: float = 2.0,
    ) -> None:
        self.url = url
        self.client_id = client_id
        host, port = _parse_url(url)
        if connect_timeout <= 0:
            raise ConfigError("fleet.mqtt.connect_timeout", "must be > 0")
        if not 0 < reconnect_delay[0] <= reconnect_delay[1]:
            raise ConfigError("fleet.mqtt.reconnect_delay", "need 0 < first <= longest")
        self._lock = threading.Condition()
        self._queues: dict[str, list[_Queue[Any]]] = {}
        self._acked: set[str] = set()
        self._pending: dict[int, str] = {}
        self._early_acks: set[int] = set()
        self._connected = False
        self._closed = False
        self._refused: str | None = None
        self._close_timeout = close_timeout
        self._in_flight: list[paho.MQTTMessageInfo] = []
        self._published = self._unsent = self._received = self._dropped = self._connects = 0
        self._reconnect_delay = reconnect_delay
        self._attempts = 0  # failed reconnection attempts since the connection was lost
        self._unsent_said = False  # an unsent message logged in this outage
        self._reconnect_listeners: list[Callable[[], None]] = []

        client = paho.Client(CallbackAPIVersion.VERSION2, client_id=client_id,
                             clean_session=True, protocol=paho.MQTTv311)
        client.on_log = self._on_log
        client.reconnect_delay_set(reconnect_delay[0], reconnect_delay[1])
        client.max_queued_messages_set(max_queued)
        if will is not None:
            topic, payload, qos, retain = will
            try:
                _check_topic(topic)
                _check_qos(qos)
            except InvalidRequest as exc:
                raise ConfigError("fleet.mqtt.will", str(exc)) from None
            client.will_set(topic, payload, qos, retain)
        client.on_connect = self._on_connect
        client.on_disconnect = self._on_disconnect
        client.on_connect_fail = self._on_connect_fail
        client.on_subscribe = self._on_subscribe
        client.on_message = self._on_message
        client.on_socket_open = _no_delay
        self._client = client
        self._start(host, port, keepalive, connect_timeout)

    # -- the Transport protocol ----------------------------------------------------------

    def publish(self, topic: str, message: Message) -> None:
        """Publish a fleet message, encoded by the codec, with its kind's QoS and retain.

        Raises:
            InvalidRequest: an empty topic or one with wildcards.
        """
        data = codec.encode(message)
        how = delivery(topic)
        self._publish(topic, data, how.qos, how.retain)

    def subscribe(self, topic: str) -> MessageInbox:
        """A new inbox for fleet messages on ``topic`` (an MQTT filter; ``+`` and ``#`` allowed).

        Raises:
            InvalidRequest: an empty or malformed filter.
        """
        inbox = MessageInbox(topic)
        self._add(inbox)
        return inbox

    # -- messages the codec does not cover --------------------------------------------------

    def publish_raw(self, topic: str, payload: bytes, qos: int | None = None,
                    retain: bool | None = None) -> None:
        """Publish ``payload`` as it is; QoS and retain default to the topic kind's
        (:data:`DELIVERY`).

        Raises:
            InvalidRequest: an empty topic, one with wildcards, or a QoS not 0, 1 or 2.
        """
        how = delivery(topic)
        self._publish(topic, payload, how.qos if qos is None else qos,
                      how.retain if retain is None else retain)

    def subscribe_raw(self, topic: str, *, version: str | None = None) -> RawInbox:
        """A new inbox for the bytes on ``topic`` (an MQTT filter).

        Args:
            topic: the filter.
            version: a VDA 5050 version (``"2.1.0"``): each message must then be JSON that
                passes the schema named by its topic's last level, or it is dropped.

        Raises:
            InvalidRequest: an empty or malformed filter, or a version with no schemas.
        """
        if version is not None and version not in validation.VERSIONS:
            raise InvalidRequest("version", f"no VDA 5050 schemas for {version!r}")
        inbox = RawInbox(topic, version)
        self._add(inbox)
        return inbox

    # -- connection state ---------------------------------------------------------------------

    def add_reconnect_listener(self, listener: Callable[[], None]) -> None:
        """Call ``listener()`` after each reconnection, once the subscriptions are sent again.

        It runs on the network thread: it must be quick and must not wait for the broker (set
        a flag for the owner's loop, or publish).
        """
        with self._lock:
            self._reconnect_listeners.append(listener)

    @property
    def connected(self) -> bool:
        """Whether the broker has accepted the connection and it has not been lost since."""
        with self._lock:
            return self._connected

    def wait_connected(self, timeout: float) -> bool:
        """Block until connected, up to ``timeout`` [s]; True if connected."""
        with self._lock:
            return self._lock.wait_for(lambda: self._connected, timeout)

    def wait_disconnected(self, timeout: float) -> bool:
        """Block until the connection is down (lost, or not yet back), up to ``timeout`` [s];
        True if it is down."""
        with self._lock:
            return self._lock.wait_for(lambda: not self._connected, timeout)

    def wait_subscribed(self, timeout: float) -> bool:
        """Block until connected and the broker has acknowledged every subscription on this
        connection, up to ``timeout`` [s]; True if so. Messages published before that may not
        reach this client."""
        with self._lock:
            return self._lock.wait_for(
                lambda: self._connected and self._acked >= set(self._queues), timeout)

    def stats(self) -> TransportStats:
        """What has been published, lost, received and dropped so far."""
        with self._lock:
            return TransportStats(self._published, self._unsent, self._received, self._dropped,
                                  self._connects)

    def close(self) -> None:
        """Disconnect cleanly (the broker then discards the will) and stop the network thread.

        QoS 1 and 2 messages still in flight are given ``close_timeout`` to be acknowledged
        first: a vehicle's OFFLINE just before it leaves must arrive, and an acknowledgement
        landing after the socket is closed makes the kernel reset the connection, which the
        broker takes for a lost client, publishing the will after all.
        """
        with self._lock:
            if self._closed:
                return
            self._closed = True
            in_flight, self._in_flight = self._in_flight, []
        deadline = time.monotonic() + self._close_timeout
        for info in in_flight:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                break
            with contextlib.suppress(ValueError, RuntimeError):  # never sent: nothing to wait for
                info.wait_for_publish(remaining)
        self._client.disconnect()
        self._client.loop_stop()
        log.info("MQTT client %s closed", self.client_id)

    def __enter__(self) -> MqttTransport:
        return self

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 trace: TracebackType | None) -> None:
        self.close()

    # -- inside ----------------------------------------------------------------------------

    def _start(self, host: str, port: int, keepalive: int, connect_timeout: float) -> None:
        """Connect, retrying with backoff until ``connect_timeout``, then start the loop."""
        deadline = time.monotonic() + connect_timeout
        delay = 0.1
        # One TCP attempt to a host that never answers blocks for at most this long (paho
        # allows setting it only before the first attempt).
        self._client.connect_timeout = connect_timeout
        while True:
            try:
                self._client.connect(host, port, keepalive)
                break
            except OSError as exc:  # refused, no route, DNS: the broker may still be starting
                reason = f"{type(exc).__name__}: {exc}"
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise BrokerUnreachable(self.url, connect_timeout, reason)
            log.debug("MQTT broker at %s not reachable (%s); retrying", self.url, reason)
            time.sleep(min(delay, remaining))
            delay = min(delay * 2, 2.0)
        self._client.loop_start()
        with self._lock:
            self._lock.wait_for(lambda: self._connected or self._refused is not None,
                                max(0.0, deadline - time.monotonic()))
            connected, refused = self._connected, self._refused
        if not connected:
            with self._lock:
                self._closed = True
            self._client.loop_stop()
            raise BrokerUnreachable(self.url, connect_timeout,
                                    refused or "the broker accepted TCP but sent no CONNACK")

    def _publish(self, topic: str, payload: bytes, qos: int, retain: bool) -> None:
        _check_topic(topic)
        _check_qos(qos)
        info = self._client.publish(topic, payload, qos, retain)
        if info.rc == MQTTErrorCode.MQTT_ERR_SUCCESS or (
            info.rc == MQTTErrorCode.MQTT_ERR_NO_CONN and qos > 0  # queued until reconnected
        ):
            wire.debug("-> %s q%d%s %s", topic, qos, " retained" if retain else "", payload)
            with self._lock:
                self._published += 1
                if qos > 0:
                    self._in_flight = [i for i in self._in_flight if not _settled(i)]
                    self._in_flight.append(info)
            return
        with self._lock:
            self._unsent += 1
            said, self._unsent_said = self._unsent_said, True
        if said:
            log.debug("MQTT message on %s not sent: %s", topic, paho.error_string(info.rc))
        else:
            log.warning("MQTT message on %s not sent: %s (more are lost until the broker is "
                        "back)", topic, paho.error_string(info.rc))

    def _add(self, queue: _Queue[Any]) -> None:
        _check_filter(queue.topic_filter)
        with self._lock:
            fresh = queue.topic_filter not in self._queues
            self._queues.setdefault(queue.topic_filter, []).append(queue)
            connected = self._connected
        if fresh and connected:
            self._send_subscribe(queue.topic_filter)

    def _send_subscribe(self, topic_filter: str) -> None:
        # Subscribe at QoS 1 so messages published at QoS 1 (connection) arrive at QoS 1.
        result, mid = self._client.subscribe(topic_filter, qos=1)
        if result != MQTTErrorCode.MQTT_ERR_SUCCESS or mid is None:
            log.warning("MQTT subscribe to %s not sent (%s); will retry on reconnect",
                        topic_filter, paho.error_string(result))
            return
        with self._lock:
            if mid in self._early_acks:  # the SUBACK beat us here
                self._early_acks.discard(mid)
                self._acked.add(topic_filter)
                self._lock.notify_all()
            else:
                self._pending[mid] = topic_filter

    def _on_connect(self, client: paho.Client, userdata: Any, flags: paho.ConnectFlags,
                    reason_code: ReasonCode, properties: Properties | None) -> None:
        if reason_code.is_failure:
            with self._lock:
                self._refused = f"the broker refused the connection: {reason_code}"
                self._lock.notify_all()
            log.error("MQTT broker at %s refused %s: %s", self.url, self.client_id, reason_code)
            return
        with self._lock:
            self._connected = True
            self._connects += 1
            reconnect = self._connects > 1
            self._attempts = 0
            self._unsent_said = False
            listeners = list(self._reconnect_listeners) if reconnect else []
            self._acked.clear()
            self._pending.clear()
            self._early_acks.clear()
            filters = list(self._queues)
            self._lock.notify_all()
        log.info("MQTT client %s %s to %s", self.client_id,
                 "reconnected" if reconnect else "connected", self.url)
        for topic_filter in filters:  # a clean session: the broker forgot our subscriptions
            self._send_subscribe(topic_filter)
        for listener in listeners:
            try:
                listener()
            except Exception:  # a listener's bug must not end the network thread
                log.exception("MQTT client %s: a reconnect listener failed", self.client_id)

    def _on_connect_fail(self, client: paho.Client, userdata: Any) -> None:
        # paho waits min(first * 2**n, longest) before its next attempt (reconnect_delay_set).
        with self._lock:
            if self._closed:
                return
            self._attempts += 1
            attempts = self._attempts
        first, longest = self._reconnect_delay
        wait = min(first * 2 ** min(attempts, 16), longest)
        log.warning("MQTT client %s: broker at %s still unreachable (attempt %d); next attempt "
                    "in %g s", self.client_id, self.url, attempts, wait)

    def _on_disconnect(self, client: paho.Client, userdata: Any,
                       flags: paho.DisconnectFlags, reason_code: ReasonCode,
                       properties: Properties | None) -> None:
        with self._lock:
            self._connected = False
            self._acked.clear()
            self._lock.notify_all()
            closing = self._closed
        if not closing:
            log.warning("MQTT client %s lost the broker at %s (%s); reconnecting",
                        self.client_id, self.url, reason_code)

    def _on_subscribe(self, client: paho.Client, userdata: Any, mid: int,
                      reason_codes: list[ReasonCode], properties: Properties | None) -> None:
        with self._lock:
            topic_filter = self._pending.pop(mid, None)
            if topic_filter is None:
                self._early_acks.add(mid)
                return
            if any(code.is_failure for code in reason_codes):
                log.error("MQTT broker refused the subscription to %s", topic_filter)
                return
            self._acked.add(topic_filter)
            self._lock.notify_all()

    def _on_log(self, client: paho.Client, userdata: Any, level: int, text: str) -> None:
        # paho reports a closed socket as an error even after a clean disconnect; only an error
        # while the transport is meant to be up deserves more than DEBUG.
        with self._lock:
            closing = self._closed
        if level == paho.MQTT_LOG_ERR and not closing:
            log.warning("paho: %s", text)
        else:
            log.debug("paho: %s", text)

    def _on_message(self, client: paho.Client, userdata: Any,
                    message: paho.MQTTMessage) -> None:
        # Runs on paho's network thread: an exception here would end the thread, and with it
        # the connection, so nothing escapes (the one broad except, as a server's per request).
        try:
            wire.debug("<- %s q%d%s %s", message.topic, message.qos,
                       " retained" if message.retain else "", message.payload)
            with self._lock:
                queues = [q for f, qs in self._queues.items()
                          if paho.topic_matches_sub(f, message.topic) for q in qs]
            delivered = dropped = 0
            for queue in queues:
                if queue.offer(message):
                    delivered += 1
                else:
                    dropped += 1
            with self._lock:
                self._received += delivered
                self._dropped += dropped
        except Exception:
            log.error("MQTT message on %s could not be handled; dropped", message.topic,
                      exc_info=True)
            with self._lock:
                self._dropped += 1


def _no_delay(client: paho.Client, userdata: Any, sock: Any) -> None:
    """Send each MQTT packet at once (``TCP_NODELAY``): paho leaves Nagle's algorithm on, and
    a small order or state written while an earlier packet is unacknowledged then waits for
    the peer's delayed ACK, up to 40 ms on Linux, on every hop. (The broker's side is its own
    setting: Mosquitto's ``set_tcp_nodelay true``, docs/fleet.md.)"""
    with contextlib.suppress(OSError, AttributeError):
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)


def _check_size(message: paho.MQTTMessage, limit: int) -> None:
    if len(message.payload) > limit:
        raise InvalidRequest("message", f"{len(message.payload)} bytes: more than the {limit} "
                             "a message may have")


def _settled(info: paho.MQTTMessageInfo) -> bool:
    try:
        return info.is_published()
    except (ValueError, RuntimeError):  # refused by paho: it will never be acknowledged
        return True


def _parse_url(url: str) -> tuple[str, int]:
    parts = urllib.parse.urlsplit(url)
    if parts.scheme != "mqtt":
        raise ConfigError("fleet.mqtt.url", f"{url!r}: must be mqtt://host[:port]")
    try:
        port = parts.port or 1883
    except ValueError:
        raise ConfigError("fleet.mqtt.url", f"{url!r}: bad port") from None
    if not parts.hostname or parts.path not in ("", "/") or parts.query:
        raise ConfigError("fleet.mqtt.url", f"{url!r}: must be mqtt://host[:port]")
    return parts.hostname, port


def _check_topic(topic: str) -> None:
    if not topic or "+" in topic or "#" in topic or "\0" in topic:
        raise InvalidRequest("topic", f"{topic!r}: must be non-empty, without wildcards")


def _check_filter(topic_filter: str) -> None:
    levels = topic_filter.split("/")
    ok = bool(topic_filter) and "\0" not in topic_filter and all(
        ("+" not in level or level == "+") and ("#" not in level or level == "#")
        for level in levels
    ) and "#" not in levels[:-1]
    if not ok:
        raise InvalidRequest("topic", f"{topic_filter!r}: not an MQTT topic filter")


def _check_qos(qos: int) -> None:
    if qos not in (0, 1, 2):
        raise InvalidRequest("qos", f"{qos!r}: must be 0, 1 or 2")

