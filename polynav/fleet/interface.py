"""The transport the fleet and its robots exchange messages over (DESIGN §9).

A transport carries :mod:`polynav.fleet.messages` between the fleet and its robots on
VDA 5050 topics (``uagv/v2/<manufacturer>/<serial>/<kind>``). Today one process holds the whole
building and the transport is :class:`~polynav.fleet.transport.InProcessTransport`; past one
machine it is an MQTT client talking to a broker, and nothing else changes. Delivery is
asynchronous as over a broker: a message published now is read by the subscriber at its next
``drain``.
"""

from __future__ import annotations

from typing import Protocol

from polynav.fleet.messages import Message, Received


class Inbox(Protocol):
    """What one subscription has received and not yet read."""

    def drain(self) -> list[Received]:
        """The messages received since the last drain, oldest first; one that could not be
        used (not JSON, breaking its schema) as a :class:`~polynav.fleet.messages.Rejected`."""
        ...

    def drain_topics(self) -> list[tuple[str, Received]]:
        """As :meth:`drain`, each message with the topic it arrived on: the reader of a
        wildcard subscription (``uagv/v2/<manufacturer>/+/state``) learns its sender there."""
        ...


class Transport(Protocol):
    """Publish messages to topics; subscribe to topics."""

    def publish(self, topic: str, message: Message) -> None: ...

    def subscribe(self, topic: str) -> Inbox: ...
