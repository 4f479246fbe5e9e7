"""The ROS graph a ROS-speaking server offers: topics, the topics clients publish, services.

A rosbridge server is a transport; what it serves is a :class:`Graph` that the dialect mappings
fill (the androidmsg interface, the standard robot topics, Galileo's ``/galileo/status``). The
graph is the seam between them, so a mapping never knows the wire and the wire never knows the
runtime, and one adapter may contribute topics to a server it does not import.

Messages are plain ``dict`` values in the ROS message's JSON form (field names and nesting of
the ``.msg`` definition, in its key order). The graph is thread-safe: the runtime's loop
publishes from its thread, the server delivers on its own.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

Message = dict[str, Any]


class RosError(Exception):
    """A publish or service call the graph refuses: the server answers with the message (a
    ``status`` error for a topic, ``result: false`` and the text for a service)."""


@dataclass(frozen=True, slots=True)
class Topic:
    """A topic the robot publishes.

    Attributes:
        name: ``/scan``.
        type: ``sensor_msgs/LaserScan``.
        latched: a new subscriber gets the last message at once (status topics, ``/map``).
    """

    name: str
    type: str
    latched: bool = False


@dataclass(frozen=True, slots=True)
class Subscription:
    """A topic the robot takes from clients (``/cmd_vel``): ``handle`` is called on a worker
    thread with each message and raises :class:`RosError` on a message it refuses."""

    name: str
    type: str
    handle: Callable[[Message], None]


@dataclass(frozen=True, slots=True)
class Service:
    """A service: ``call`` gets the request's ``args`` and returns the response's values, on a
    worker thread (it may wait for the runtime); it raises :class:`RosError` to fail."""

    name: str
    type: str
    call: Callable[[Message], Message]


Sink = Callable[[str, Message], None]


class Graph:
    """Topics, subscriptions and services by name, and the sinks published messages go to."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._topics: dict[str, Topic] = {}
        self._subscriptions: dict[str, Subscription] = {}
        self._services: dict[str, Service] = {}
        self._last: dict[str, Message] = {}
        self._sinks: list[Sink] = []
        self._interest: dict[str, int] = {}

    # -- what mappings declare -------------------------------------------------------------------

    def add_topic(self, topic: Topic) -> Topic:
        """Declare a topic the robot publishes.

        Raises:
            ValueError: the name is taken by another topic.
        """
        with self._lock:
            if topic.name in self._topics:
                raise ValueError(f"topic {topic.name} is declared twice")
            self._topics[topic.name] = topic
        return topic

    def add_subscription(self, subscription: Subscription) -> None:
        """Declare a topic the robot takes from clients.

        Raises:
            ValueError: the name is taken by another subscription.
        """
        with self._lock:
            if subscription.name in self._subscriptions:
                raise ValueError(f"subscription {subscription.name} is declared twice")
            self._subscriptions[subscription.name] = subscription

    def add_service(self, service: Service) -> None:
        """Declare a service.

        Raises:
            ValueError: the name is taken.
        """
        with self._lock:
            if service.name in self._services:
                raise ValueError(f"service {service.name} is declared twice")
            self._services[service.name] = service

    def publish(self, name: str, message: Message) -> None:
        """Hand ``message`` to every sink (any thread; sinks must not block).

        Raises:
            KeyError: no topic of that name was declared.
        """
        with self._lock:
            topic = self._topics[name]
            if topic.latched:
                self._last[name] = message
            sinks = tuple(self._sinks)
        for sink in sinks:
            sink(name, message)

    def wanted(self, name: str) -> bool:
        """Whether a client subscribes to ``name`` now: a mapping builds a message only then,
        so a stream at 150 Hz costs nothing while no one listens (latched topics are
        published regardless, to be remembered)."""
        return self._interest.get(name, 0) > 0

    # -- what servers read -----------------------------------------------------------------------

    def add_sink(self, sink: Sink) -> Callable[[], None]:
        """Receive every published message; returns the function that stops it."""
        with self._lock:
            self._sinks.append(sink)

        def remove() -> None:
            with self._lock:
                if sink in self._sinks:
                    self._sinks.remove(sink)

        return remove

    def retain(self, name: str) -> None:
        """A server has a subscriber of ``name`` (one call per subscribing client)."""
        with self._lock:
            self._interest[name] = self._interest.get(name, 0) + 1

    def release(self, name: str) -> None:
        """A subscriber of ``name`` has gone."""
        with self._lock:
            left = self._interest.get(name, 0) - 1
            if left > 0:
                self._interest[name] = left
            else:
                self._interest.pop(name, None)

    def topic(self, name: str) -> Topic | None:
        with self._lock:
            return self._topics.get(name)

    def subscription(self, name: str) -> Subscription | None:
        with self._lock:
            return self._subscriptions.get(name)

    def service(self, name: str) -> Service | None:
        with self._lock:
            return self._services.get(name)

    def latched(self, name: str) -> Message | None:
        """The last message of a latched topic, if any."""
        with self._lock:
            return self._last.get(name)

    def topics(self) -> list[Topic]:
        """Every topic a client may subscribe to or publish on, published ones first."""
        with self._lock:
            return list(self._topics.values())

    def subscriptions(self) -> list[Subscription]:
        with self._lock:
            return list(self._subscriptions.values())

    def services(self) -> list[Service]:
        with self._lock:
            return list(self._services.values())
