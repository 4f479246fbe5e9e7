"""The in-process transport: topics and queues in memory, every message through the JSON codec.

Each message is encoded on publish and decoded on drain, exactly the bytes an MQTT broker would
carry (:mod:`polynav.fleet.codec`), so the in-process building cannot come to rely on sharing
Python objects between the fleet and a robot. Publishing and draining are thread-safe (a deque
per subscription).
"""

from __future__ import annotations

import logging
import threading
from collections import deque

from polynav.errors import InvalidRequest
from polynav.fleet import codec
from polynav.fleet.messages import Message, Received, Rejected

log = logging.getLogger(__name__)
wire = logging.getLogger("polynav.fleet.wire")


class QueueInbox:
    """One subscription's queue of encoded messages."""

    def __init__(self, kind: str) -> None:
        self._kind = kind
        self._queue: deque[tuple[str, bytes]] = deque()

    def put(self, topic: str, data: bytes) -> None:
        self._queue.append((topic, data))

    def drain(self) -> list[Received]:
        """The messages since the last drain, oldest first; one that cannot be used (not JSON,
        breaking its schema) as a :class:`~polynav.fleet.messages.Rejected`."""
        return [item for _, item in self.drain_topics()]

    def drain_topics(self) -> list[tuple[str, Received]]:
        """As :meth:`drain`, each message with the topic it was published on."""
        out = []
        while self._queue:
            topic, data = self._queue.popleft()
            item = codec.read(self._kind, data)
            if isinstance(item, Rejected):
                log.warning("refused a %s message on %s: %s", self._kind, topic, item.reason)
            out.append((topic, item))
        return out


class InProcessTransport:
    """Topics in memory. ``published`` counts messages, for figures and tests."""

    def __init__(self) -> None:
        self._subscribers: dict[str, list[QueueInbox]] = {}
        self._filters: list[tuple[tuple[str, ...], QueueInbox]] = []
        self._lock = threading.Lock()
        self.published = 0

    def subscribe(self, topic: str) -> QueueInbox:
        """A new inbox for ``topic``: a topic, or a filter with MQTT's single-level wildcard
        ``+`` (``uagv/v2/polynav/+/connection``: every robot's); the last level names the
        message kind, so it is never a wildcard.

        Raises:
            InvalidRequest: an empty topic, a ``#``, a ``+`` inside a level or as the last one.
        """
        levels = topic.split("/")
        if not topic or "#" in topic or levels[-1] == "+" or any(
                "+" in level and level != "+" for level in levels):
            raise InvalidRequest("topic", f"{topic!r}: a topic, or one with whole-level '+' "
                                          "before its last level")
        inbox = QueueInbox(levels[-1])
        with self._lock:
            if "+" in levels:
                self._filters.append((tuple(levels), inbox))
            else:
                self._subscribers.setdefault(topic, []).append(inbox)
        return inbox

    def publish(self, topic: str, message: Message) -> None:
        """Publish ``message``, encoded (and checked against its schema) by the codec.

        Raises:
            SchemaViolation: the message breaks its VDA 5050 schema (a bug in its sender).
        """
        self.publish_raw(topic, codec.encode(message))

    def publish_raw(self, topic: str, data: bytes) -> None:
        """Publish ``data`` as it is (subscribers decode it; what does not decode reaches them
        as :class:`~polynav.fleet.messages.Rejected`)."""
        wire.debug("-> %s %s", topic, data)
        with self._lock:
            inboxes = list(self._subscribers.get(topic, ()))
            if self._filters:
                levels = topic.split("/")
                inboxes += [inbox for pattern, inbox in self._filters
                            if _matches(pattern, levels)]
            self.published += 1
        for inbox in inboxes:
            inbox.put(topic, data)


def _matches(pattern: tuple[str, ...], levels: list[str]) -> bool:
    return len(pattern) == len(levels) and all(
        p in ("+", level) for p, level in zip(pattern, levels, strict=True))
