"""polynav's rosbridge server with the androidmsg interface and the robot's streams, over a
simulated runtime on the demo site; a raw rosbridge client on the wire.

As the other dialect suites: the runtime's loop thread is not started; handlers run runtime
commands at once under its lock, and the test advances simulated time itself between requests.
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable, Iterator
from typing import Any

import pytest

from polynav.protocols.ros_graph import Graph
from polynav.protocols.rosbridge.androidmsg import add_androidmsg, ids
from polynav.protocols.rosbridge.robot_topics import add_robot_topics
from polynav.protocols.site_store import site_store
from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds.world import World
from tests.protocols.rosbridge.conftest import Client, rosbridge


class Robot:
    """The runtime, its graph, the server and a client."""

    def __init__(self, runtime: RobotRuntime, graph: Graph, client: Client) -> None:
        self.runtime = runtime
        self.graph = graph
        self.client = client
        self.store = site_store(runtime)
        self.site = ids.Site(self.store)
        self.seen: dict[str, list[Any]] = {}
        self._ids = 0

    def start_navigation(self) -> None:
        """Navigating on floor1 from its initial point, localized."""
        self.runtime.start_navigation("floor1", point="initial")
        self.runtime.advance(1.0)

    def call(self, service: str, args: dict[str, Any] | None = None) -> dict[str, Any]:
        """A call that must succeed: its values."""
        reply = self._call(service, args if args is not None else {})
        assert reply["result"] is True, reply
        values: dict[str, Any] = reply["values"]
        return values

    def fail(self, service: str, args: dict[str, Any]) -> str:
        """A call that must fail: its reason."""
        reply = self._call(service, args)
        assert reply["result"] is False, reply
        return str(reply["values"])

    def status_error(self, frame: dict[str, Any]) -> str:
        """Send ``frame`` (with an id) and return the status error it gets."""
        self.client.send(frame)
        while True:
            got = self._next(timeout=10.0)
            if got.get("op") == "status" and got.get("id") == frame["id"]:
                return str(got["msg"])

    def subscribe(self, topic: str) -> None:
        self.client.send({"op": "subscribe", "topic": topic, "queue_length": 100})
        self._call("/rosapi/get_time", {})

    def publish(self, topic: str, msg: dict[str, Any]) -> None:
        self.client.send({"op": "publish", "topic": topic, "msg": msg})
        self._call("/rosapi/get_time", {})  # handled after the publish has been

    def codes(self, topic: str, until: Callable[[list[int]], bool], timeout: float = 60.0,
              step: float = 0.1) -> list[int]:
        """Every code received on ``topic`` so far, advancing simulated time until
        ``until(codes)``."""
        deadline = self.runtime.now() + timeout
        while True:
            with contextlib.suppress(TimeoutError):
                while True:
                    self._next(timeout=0.02)
            got = self.seen.get(topic, [])
            if until(got):
                return got
            assert self.runtime.now() < deadline, (topic, got)
            self.runtime.advance(step)

    def _call(self, service: str, args: dict[str, Any]) -> dict[str, Any]:
        self._ids += 1
        ident = f"call-{self._ids}"
        self.client.send({"op": "call_service", "id": ident, "service": service, "args": args})
        while True:
            got = self._next(timeout=30.0)
            if got.get("op") == "service_response" and got.get("id") == ident:
                return got

    def _next(self, timeout: float) -> dict[str, Any]:
        frame = self.client.recv(timeout=timeout)
        if frame.get("op") == "publish":
            self.seen.setdefault(frame["topic"], []).append(frame["msg"].get("data"))
        return frame

    def ids_of(self, map_name: str, point: str) -> dict[str, int]:
        floor = self.site.floor_of_map(map_name)
        assert floor is not None
        p = self.store.point(map_name, point)
        return {"floor_id": floor.level, "map_id": ids.map_id(map_name),
                "point_id": ids.point_id(p)}

    def wait(self, done: Callable[[], bool], timeout: float = 60.0) -> bool:
        end = time.monotonic() + 30
        deadline = self.runtime.now() + timeout
        while not done():
            if self.runtime.now() >= deadline or time.monotonic() > end:
                return False
            self.runtime.advance(0.1)
        return True


@pytest.fixture
def robot(world: World, store: SiteStore) -> Iterator[Robot]:
    runtime = RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False))
    graph = Graph()
    detach = [add_robot_topics(graph, runtime), add_androidmsg(graph, runtime)]
    runtime.advance(0.2)
    with rosbridge(graph, runtime.clock) as server:
        client = Client(server.port)
        try:
            yield Robot(runtime, graph, client)
        finally:
            client.close()
    for remove in detach:
        remove()
