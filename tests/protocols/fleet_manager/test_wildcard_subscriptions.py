"""The fleet manager listens with wildcards (issue #36): over a real Mosquitto, its SUBSCRIBE
packets (paho's log of what it sends) do not grow with the robots, a robot that joins after
it started is heard, and a state whose header names another robot than its topic is dropped
with one log line, the manager going on."""

from __future__ import annotations

import logging
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

from polynav.fleet import messages as m
from polynav.fleet.manager import FleetManager
from polynav.fleet.mqtt_transport import MessageInbox, MqttTransport
from polynav.fleet.records import FleetRecords
from tests.helpers.mosquitto import Mosquitto
from tests.helpers.scripted_vehicle import Robot, Site

WAIT = 10.0  # [s of wall time] for a message through the broker
TRANSPORT_LOG = "polynav.fleet.mqtt_transport"


@pytest.fixture
def records(tmp_path: Path) -> Iterator[FleetRecords]:
    with FleetRecords.open(f"sqlite:///{tmp_path / 'fleet.db'}", name="fm1") as opened:
        yield opened


@pytest.fixture
def clients(broker: Mosquitto) -> Iterator[Callable[[str], MqttTransport]]:
    """Connections to ``broker`` by client id, each closed at the end."""
    opened: list[MqttTransport] = []

    def connect(client_id: str) -> MqttTransport:
        opened.append(MqttTransport(broker.url, client_id))
        return opened[-1]

    yield connect
    for client in reversed(opened):
        client.close()


class Ticker:
    """The manager ticked on site time, 10 ms of wall time per 0.1 s tick, until a condition."""

    def __init__(self, manager: FleetManager) -> None:
        self.manager = manager
        self.now = 0.0

    def until(self, done: Callable[[], bool]) -> bool:
        deadline = time.monotonic() + WAIT
        while time.monotonic() < deadline:
            self.now += 0.1
            self.manager.tick(self.now)
            if done():
                return True
            time.sleep(0.01)
        return False


def _manager_subscribes(caplog: pytest.LogCaptureFixture) -> list[str]:
    """The SUBSCRIBE packets sent for the kinds robots send (connection, state, zoneRequest):
    the manager's (paho logs each packet it sends)."""
    return [line for line in (r.getMessage() for r in caplog.records if r.name == TRANSPORT_LOG)
            if "Sending SUBSCRIBE" in line
            and any(f"/{kind}'" in line for kind in ("connection", "state", "zoneRequest"))]


def _took(into: list[m.GrantType], more: list[m.GrantType]) -> bool:
    into.extend(more)
    return bool(into)


def _heard(manager: FleetManager, serial: str) -> bool:
    return any(r.serial == serial and r.state is not None for r in manager.robots())


class Redirected:
    """A robot's transport that publishes on another robot's topics (a misconfigured robot
    speaking in another's name)."""

    def __init__(self, inner: MqttTransport, own: str, other: str) -> None:
        self.inner, self.own, self.other = inner, own, other

    def publish(self, topic: str, message: m.Message) -> None:
        self.inner.publish(topic.replace(f"/{self.own}/", f"/{self.other}/"), message)

    def subscribe(self, topic: str) -> MessageInbox:
        return self.inner.subscribe(topic)


def test_the_subscriptions_do_not_grow_with_the_robots(
        clients: Callable[[str], MqttTransport], records: FleetRecords,
        caplog: pytest.LogCaptureFixture) -> None:
    caplog.set_level(logging.DEBUG, logger=TRANSPORT_LOG)
    mqtt = clients("test/fleet")
    manager = FleetManager(mqtt, records, Site())
    assert mqtt.wait_subscribed(WAIT)
    at_start = _manager_subscribes(caplog)
    assert len(at_start) == 3, at_start  # connection, state, zoneRequest: a wildcard each
    assert all("uagv/v2/polynav/+/" in line for line in at_start), at_start
    side = clients("test/robots")
    robots = [Robot(side, f"r{k}", float(k)) for k in range(1, 31)]
    assert side.wait_subscribed(WAIT)
    for robot in robots:
        robot.connection(m.ConnectionState.ONLINE)
        robot.state()
    ticker = Ticker(manager)
    assert ticker.until(lambda: all(_heard(manager, r.serial) for r in robots)), \
        [r.serial for r in manager.robots() if r.state is None]
    robots[0].ask("lift")
    got: list[m.GrantType] = []
    assert ticker.until(lambda: _took(got, robots[0].grants()))
    # Thirty robots heard and answered, and the manager sent no SUBSCRIBE after its three
    # (the robots' own subscriptions, on their own connection, are to exact topics of the
    # kinds the manager sends).
    assert _manager_subscribes(caplog) == at_start


def test_a_robot_joining_after_start_is_heard_and_answered(
        clients: Callable[[str], MqttTransport], records: FleetRecords) -> None:
    mqtt = clients("test/fleet")
    manager = FleetManager(mqtt, records, Site())
    assert mqtt.wait_subscribed(WAIT)
    ticker = Ticker(manager)
    for _ in range(5):
        ticker.until(lambda: True)
    assert manager.robots() == []
    # It joins now, and says only its state (its connection message is not needed to be
    # heard): it is adopted, ONLINE, and its zone requests are answered.
    late_client = clients("test/late")
    late = Robot(late_client, "late", 4.0)
    assert late_client.wait_subscribed(WAIT)
    late.state()
    assert ticker.until(lambda: _heard(manager, "late"))
    view = manager.robot("late")
    assert view.connection == m.ConnectionState.ONLINE.value
    assert view.state is not None and view.state.agv_position is not None
    assert view.state.agv_position.x == 4.0
    late.ask("door")
    got: list[m.GrantType] = []
    assert ticker.until(lambda: _took(got, late.grants()))
    assert got == [m.GrantType.GRANTED]
    assert [e.detail["robot"] for e in manager.events_after(0)
            if e.kind == "robot.connection"] == ["late"]


def _manager_and_robots_link(clients: Callable[[str], MqttTransport], records: FleetRecords
                             ) -> tuple[FleetManager, MqttTransport]:
    """A fleet manager listening on the broker, and the link the test's robots speak on."""
    mqtt = clients("test/fleet")
    manager = FleetManager(mqtt, records, Site())
    assert mqtt.wait_subscribed(WAIT)
    return manager, clients("test/robots")


def test_a_state_whose_header_disagrees_with_its_topic_is_dropped_with_one_log_line(
        clients: Callable[[str], MqttTransport], records: FleetRecords,
        caplog: pytest.LogCaptureFixture) -> None:
    caplog.set_level(logging.WARNING, logger="polynav.fleet.master_control")
    manager, side = _manager_and_robots_link(clients, records)
    honest = Robot(side, "r1", 1.0)
    # r2's messages go out on r1's topics: its headers say r2.
    impostor = Robot(Redirected(side, "r2", "r1"), "r2", 9.0)
    assert side.wait_subscribed(WAIT)
    honest.connection(m.ConnectionState.ONLINE)
    honest.state()
    ticker = Ticker(manager)
    assert ticker.until(lambda: _heard(manager, "r1"))
    for _ in range(3):
        impostor.state()
    impostor.ask("lift")
    honest.state()  # after the impostor's: once it is read, theirs have been too
    before = manager.master.mismatched
    assert ticker.until(lambda: manager.master.mismatched >= before + 4)
    # Dropped: r1's state is its own, r2 is no robot of the fleet, and nothing was granted.
    assert [r.serial for r in manager.robots()] == ["r1"]
    state = manager.robot("r1").state
    assert state is not None and state.header.serial_number == "r1"
    assert state.agv_position is not None and state.agv_position.x == 1.0
    assert honest.grants() == []
    lines = [r.getMessage() for r in caplog.records
             if r.name == "polynav.fleet.master_control" and "dropped" in r.getMessage()]
    assert len(lines) == 2, lines  # once for the state topic, once for the zoneRequest one
    assert any("uagv/v2/polynav/r1/state" in line and "polynav/r2" in line for line in lines)
    # The manager goes on: r1 is still heard.
    honest.x = 2.0
    honest.state()
    assert ticker.until(lambda: (s := manager.robot("r1").state) is not None
                        and s.agv_position is not None and s.agv_position.x == 2.0)


class OtherMaker(Robot):
    """A robot whose headers name another manufacturer than its topics'."""

    def _header(self) -> m.Header:
        header = super()._header()
        return m.Header(header.header_id, header.timestamp, header.version, "acme",
                        header.serial_number)


def test_a_state_of_another_manufacturer_on_our_topic_adopts_no_one(
        clients: Callable[[str], MqttTransport], records: FleetRecords,
        caplog: pytest.LogCaptureFixture) -> None:
    caplog.set_level(logging.WARNING, logger="polynav.fleet.master_control")
    manager, side = _manager_and_robots_link(clients, records)
    stranger, honest = OtherMaker(side, "s1", 3.0), Robot(side, "r1", 1.0)
    assert side.wait_subscribed(WAIT)
    stranger.state()
    stranger.state()
    honest.state()
    ticker = Ticker(manager)
    assert ticker.until(lambda: _heard(manager, "r1") and manager.master.mismatched == 2)
    assert [r.serial for r in manager.robots()] == ["r1"]
    lines = [r.getMessage() for r in caplog.records if "dropped" in r.getMessage()]
    assert len(lines) == 1 and "acme/s1" in lines[0], lines
