"""A robot's end of a fleet transport, scripted by the test (connection, states, zone
requests), and a small site of named points: for tests of the fleet manager without a
simulator."""

from __future__ import annotations

from polynav.errors import NotFound
from polynav.fleet import messages as m
from polynav.fleet.interface import Transport
from polynav.geometry import Pose2D
from polynav.site import Point

POINTS = {("floor1", "desk"): (10.0, 0.0), ("floor1", "door"): (0.0, 0.0),
          ("floor2", "ward"): (5.0, 5.0)}


class Site:
    def point(self, map_name: str, name: str) -> Point:
        if (map_name, name) not in POINTS:
            raise NotFound("point", f"{map_name}/{name}")
        x, y = POINTS[(map_name, name)]
        return Point(name, map_name, Pose2D(x, y, 0.0))


class Robot:
    """A robot's end of the transport, scripted: it says what the test tells it to."""

    def __init__(self, transport: Transport, serial: str, x: float = 0.0) -> None:
        self.transport, self.serial, self.x = transport, serial, x
        self.orders = transport.subscribe(m.topic(serial, m.Order))
        self.actions = transport.subscribe(m.topic(serial, m.InstantActions))
        self.responses = transport.subscribe(m.topic(serial, m.ZoneResponse))
        self.header = 0

    def _header(self) -> m.Header:
        self.header += 1
        return m.Header(self.header, "2026-11-28T11:40:03.120Z", "2.0.0", "polynav",
                        self.serial)

    def connection(self, state: m.ConnectionState) -> None:
        self.transport.publish(m.topic(self.serial, m.Connection),
                               m.Connection(self._header(), state))

    def state(self, order_id: str = "", *, nodes: int = 0, failed: bool = False,
              battery: float = 90.0) -> None:
        refs = (m.ErrorReference("orderId", order_id),)
        self.transport.publish(m.topic(self.serial, m.State), m.State(
            header=self._header(), order_id=order_id, order_update_id=0,
            last_node_id="", last_node_sequence_id=0,
            node_states=tuple(m.NodeState(f"n{k}", 2 * k, True) for k in range(nodes)),
            edge_states=(), driving=nodes > 0, operating_mode="AUTOMATIC",
            battery_state=m.BatteryState(battery, False),
            agv_position=m.AgvPosition(self.x, 0.0, 0.0, "floor1", True),
            errors=(m.ErrorEntry("orderFailed", "WARNING", "blocked", refs),) if failed else ()))

    def order_ids(self) -> list[str]:
        out = []
        for order in self.orders.drain():
            assert isinstance(order, m.Order)
            out.append(order.order_id)
        return out

    def ask(self, zone: str) -> None:
        self.transport.publish(m.topic(self.serial, m.ZoneRequest), m.ZoneRequest(
            self.header, self.serial, f"{zone}-{self.header}", zone,
            m.ZoneRequestType.ACCESS, 10.0))

    def release(self, zone: str) -> None:
        self.header += 1
        self.transport.publish(m.topic(self.serial, m.ZoneRequest), m.ZoneRequest(
            self.header, self.serial, f"{zone}-release-{self.header}", zone,
            m.ZoneRequestType.RELEASE))

    def grants(self) -> list[m.GrantType]:
        out = []
        for r in self.responses.drain():
            assert isinstance(r, m.ZoneResponse)
            out.append(r.grant_type)
        return out
