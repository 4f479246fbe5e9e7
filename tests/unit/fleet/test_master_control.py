"""Master control over the in-process transport: orders out, zone requests answered."""

from __future__ import annotations

import math

import pytest

from polynav.errors import InvalidRequest
from polynav.fleet import messages as m
from polynav.fleet.master_control import MasterControl, Stop
from polynav.fleet.transport import InProcessTransport
from polynav.geometry import Pose2D
from polynav.leases.book import LeaseBook, LeaseBookConfig


class Robot:
    """The robot's end of the transport, scripted."""

    def __init__(self, transport: InProcessTransport, serial: str) -> None:
        self.serial = serial
        self.transport = transport
        self.orders = transport.subscribe(m.topic(serial, m.Order))
        self.actions = transport.subscribe(m.topic(serial, m.InstantActions))
        self.responses = transport.subscribe(m.topic(serial, m.ZoneResponse))

    def ask(self, request_id: str, zone: str,
            kind: m.ZoneRequestType = m.ZoneRequestType.ACCESS, flow: str | None = None) -> None:
        self.transport.publish(m.topic(self.serial, m.ZoneRequest),
                               m.ZoneRequest(1, self.serial, request_id, zone, kind, 10.0, flow))

    def answers(self) -> list[tuple[str, m.GrantType, float | None]]:
        out = []
        for r in self.responses.drain():
            assert isinstance(r, m.ZoneResponse)
            out.append((r.request_id, r.grant_type, r.lease_expiry))
        return out


@pytest.fixture
def setup() -> tuple[MasterControl, Robot, Robot]:
    transport = InProcessTransport()
    master = MasterControl(transport, LeaseBook(LeaseBookConfig(max_wait=20.0)))
    master.add_robot("r1")
    master.add_robot("r2")
    return master, Robot(transport, "r1"), Robot(transport, "r2")


def state(serial: str, *, at: tuple[float, float] | None = (0.5, 1.5),
          last_node: str = "") -> m.State:
    """A robot's state, standing at ``at`` on floor1 (nowhere if None)."""
    return m.State(
        header=m.Header(0, "2026-11-28T11:40:03.120Z", "2.0.0", "polynav", serial),
        order_id="", order_update_id=0, last_node_id=last_node, last_node_sequence_id=0,
        node_states=(), edge_states=(), driving=False, operating_mode="AUTOMATIC",
        battery_state=m.BatteryState(90.0, False),
        agv_position=None if at is None else m.AgvPosition(at[0], at[1], 0.2, "floor1", True),
    )


def test_order_starts_where_the_robot_stands_and_reaches_only_its_robot(
        setup: tuple[MasterControl, Robot, Robot]) -> None:
    master, r1, r2 = setup
    with pytest.raises(InvalidRequest, match="has not said where it is"):
        master.send_order("r1", [Stop("office_1", "floor1", Pose2D(1.0, 2.0, 0.5))])
    r1.transport.publish(m.topic("r1", m.State), state("r1", last_node="lobby"))
    master.tick(0.0)
    order_id = master.send_order("r1", [Stop("office_1", "floor1", Pose2D(1.0, 2.0, 0.5)),
                                        Stop("office_2", "floor1", Pose2D(3.0, 2.0, 7.0))])
    (order,) = r1.orders.drain()
    assert isinstance(order, m.Order) and order.order_id == order_id
    assert [(n.node_id, n.sequence_id, n.released) for n in order.nodes] == [
        ("lobby", 0, True), ("office_1", 2, True), ("office_2", 4, True)]
    assert order.nodes[0].node_position == m.NodePosition(0.5, 1.5, 0.2, "floor1")
    assert order.nodes[1].node_position == m.NodePosition(1.0, 2.0, 0.5, "floor1")
    position = order.nodes[2].node_position
    assert position is not None and position.theta == pytest.approx(7.0 - 2 * math.pi)
    assert [(e.start_node_id, e.end_node_id, e.sequence_id) for e in order.edges] == [
        ("lobby", "office_1", 1), ("office_1", "office_2", 3)]
    assert (order.header.serial_number, order.header.version) == ("r1", "2.0.0")
    assert r2.orders.drain() == []
    master.cancel_order("r1")
    master.cancel_order("r1")
    actions = r1.actions.drain()
    assert all(isinstance(a, m.InstantActions) for a in actions)
    assert [a.header.header_id for a in actions if isinstance(a, m.InstantActions)] == [0, 1]
    first = actions[0]
    assert isinstance(first, m.InstantActions)
    assert first.actions[0].action_type == m.ActionType.CANCEL_ORDER.value


def test_zone_is_granted_queued_then_granted_to_the_waiter_on_release(
        setup: tuple[MasterControl, Robot, Robot]) -> None:
    master, r1, r2 = setup
    r1.ask("a", "zone:floor1/1")
    r2.ask("b", "zone:floor1/1")
    master.tick(1.0)
    assert r1.answers() == [("a", m.GrantType.GRANTED, 11.0)]
    assert r2.answers() == [("b", m.GrantType.QUEUED, None)]
    r1.ask("a", "zone:floor1/1", m.ZoneRequestType.RELEASE)
    master.tick(2.0)
    assert r2.answers() == [("b", m.GrantType.GRANTED, 12.0)]


def test_robots_going_the_same_way_are_granted_a_zone_together(
        setup: tuple[MasterControl, Robot, Robot]) -> None:
    master, r1, r2 = setup
    r1.ask("a", "zone:floor1/1", flow="E")
    r2.ask("b", "zone:floor1/1", flow="E")
    master.tick(1.0)
    assert r1.answers() == [("a", m.GrantType.GRANTED, 11.0)]
    assert r2.answers() == [("b", m.GrantType.GRANTED, 11.0)]


def test_each_waiter_is_told_its_place_in_line_again_when_it_changes(
        setup: tuple[MasterControl, Robot, Robot]) -> None:
    master, r1, r2 = setup
    master.add_robot("r3")
    r3 = Robot(r1.transport, "r3")
    r1.ask("a", "zone:floor1/1")
    r2.ask("b", "zone:floor1/1")
    r3.ask("c", "zone:floor1/1")
    master.tick(1.0)
    assert _places(r2) == [("b", m.GrantType.QUEUED, 0)]
    assert _places(r3) == [("c", m.GrantType.QUEUED, 1)]
    master.tick(2.0)
    assert _places(r2) == [] and _places(r3) == []  # told once, not at every tick
    r3.ask("c", "zone:floor1/1")  # a request repeated is answered again
    master.tick(2.5)
    assert _places(r3) == [("c", m.GrantType.QUEUED, 1)]
    r1.ask("a", "zone:floor1/1", m.ZoneRequestType.RELEASE)
    master.tick(3.0)
    assert _places(r2) == [("b", m.GrantType.GRANTED, None)]
    assert _places(r3) == [("c", m.GrantType.QUEUED, 0)]  # next now: it moves up


def _places(robot: Robot) -> list[tuple[str, m.GrantType, int | None]]:
    out = []
    for r in robot.responses.drain():
        assert isinstance(r, m.ZoneResponse)
        out.append((r.request_id, r.grant_type, r.queue_position))
    return out


def test_renewal_extends_and_silence_expires(setup: tuple[MasterControl, Robot, Robot]) -> None:
    master, r1, _ = setup
    r1.ask("a", "zone:floor1/1")
    master.tick(0.0)
    r1.ask("a", "zone:floor1/1")
    master.tick(5.0)
    assert r1.answers() == [("a", m.GrantType.GRANTED, 10.0), ("a", m.GrantType.GRANTED, 15.0)]
    master.tick(15.0)
    assert r1.answers() == [("a", m.GrantType.EXPIRED, None)]


def test_a_waiter_is_rejected_after_max_wait(setup: tuple[MasterControl, Robot, Robot]) -> None:
    master, r1, r2 = setup
    r1.ask("a", "zone:floor1/1")
    r2.ask("b", "zone:floor1/1")
    master.tick(0.0)
    for t in range(1, 21):
        if t % 5 == 0:
            r1.ask("a", "zone:floor1/1")  # r1 renews, keeping the zone
        master.tick(float(t))
    assert ("b", m.GrantType.REJECTED, None) in r2.answers()


def test_state_is_kept_per_robot_and_a_broken_one_is_not_used(
        setup: tuple[MasterControl, Robot, Robot]) -> None:
    master, r1, _ = setup
    kept = state("r1")
    r1.transport.publish(m.topic("r1", m.State), kept)
    assert master.state("r1") is None
    master.tick(3.0)
    assert master.state("r1") == kept and master.state("r2") is None
    assert master.state_time("r1") == 3.0
    broken = m.State(**{**{f: getattr(kept, f) for f in kept.__dataclass_fields__},
                        "operating_mode": "RACING"})
    with pytest.raises(InvalidRequest):  # polynav never sends it...
        r1.transport.publish(m.topic("r1", m.State), broken)
    # ...and a stranger's bytes that break the schema are not used either.
    inbox = r1.transport.subscribe(m.topic("r1", m.State))
    r1.transport.publish_raw(m.topic("r1", m.State), b'{"headerId": 1, "version": "2.0.0"}')
    master.tick(4.0)
    assert master.state("r1") == kept and master.state_time("r1") == 3.0
    (rejected,) = inbox.drain()
    assert isinstance(rejected, m.Rejected) and rejected.field == "$.timestamp"


def test_unknown_or_duplicate_robots_are_refused(
        setup: tuple[MasterControl, Robot, Robot]) -> None:
    master, _, _ = setup
    with pytest.raises(InvalidRequest):
        master.add_robot("r1")
    with pytest.raises(InvalidRequest):
        master.send_order("r9", [Stop("a", "floor1", Pose2D(0.0, 0.0, 0.0))])
    with pytest.raises(InvalidRequest):
        master.send_order("r1", [])
