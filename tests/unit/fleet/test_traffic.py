"""One robot's side of the traffic rule: what it asks for, when it stops, when it may go."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from polynav.fleet import messages as m
from polynav.fleet.traffic import TrafficConfig, TrafficRule
from polynav.fleet.zones import find_zones
from polynav.geometry import Pose2D
from polynav.maps.map import Map
from polynav.nav.attempt import NavigationState
from polynav.planning.path import Path
from polynav.runtime import events
from tests.unit.fleet.test_zones import _two_rooms


@dataclass
class _Navigator:
    path: Path
    state: NavigationState = NavigationState.RUNNING


@dataclass
class _Stack:
    navigator: _Navigator


@dataclass
class _Status:
    pose: Pose2D
    attempt_id: int | None = 1


@dataclass
class _Robot:
    """The few things of a robot runtime the rule reads and does."""

    pose: Pose2D
    path: Path
    map_name: str = "m"
    navigation_stack: _Stack = field(init=False)
    published: list[events.RuntimeEvent] = field(default_factory=list)

    def __post_init__(self) -> None:
        self.navigation_stack = _Stack(_Navigator(self.path))

    def status(self) -> _Status:
        return _Status(self.pose)

    def now(self) -> float:
        return 0.0

    def publish(self, event: events.RuntimeEvent) -> None:
        self.published.append(event)

    def pause(self) -> None:
        self.navigation_stack.navigator.state = NavigationState.PAUSED

    def resume(self) -> None:
        self.navigation_stack.navigator.state = NavigationState.RUNNING


def _rule(sent: list[tuple[str, str, m.ZoneRequestType]],
          flows: list[str | None] | None = None) -> TrafficRule:
    zones = {"m": find_zones("m", _two_rooms(1.0))}

    def send(rid: str, zone: str, kind: m.ZoneRequestType, _duration: float,
             flow: str | None = None) -> None:
        sent.append((rid, zone, kind))
        if flows is not None:
            flows.append(flow)

    return TrafficRule("r1", zones, TrafficConfig(), send)


def _queued(rule: TrafficRule, sent: list[tuple[str, str, m.ZoneRequestType]]) -> None:
    rid, zone, _ = sent[-1]
    rule.on_response(m.ZoneResponse(header_id=1, serial_number="r1", request_id=rid,
                                    zone_id=zone, grant_type=m.GrantType.QUEUED))


def test_a_robot_at_a_doors_edge_heading_through_it_waits_for_the_lease() -> None:
    sent: list[tuple[str, str, m.ZoneRequestType]] = []
    flows: list[str | None] = []
    rule = _rule(sent, flows)
    robot = _Robot(Pose2D(4.6, 2.0, np.pi), Path(np.array([[4.6, 2.0], [1.0, 2.0]])))
    rule.tick(0.0, robot)  # type: ignore[arg-type]
    assert [(z, k) for _, z, k in sent] == [("zone:m/1", m.ZoneRequestType.ACCESS)]
    assert flows == ["WW"]  # the way it goes through: others going west may share the door
    _queued(rule, sent)
    rule.tick(1.0, robot)  # type: ignore[arg-type]
    assert rule.waiting_for == "zone:m/1"
    assert robot.navigation_stack.navigator.state is NavigationState.PAUSED


def test_a_robot_at_a_doors_edge_heading_away_leaves_without_a_lease() -> None:
    # Waiting there, it would wall in whoever holds the door and must come out of it.
    sent: list[tuple[str, str, m.ZoneRequestType]] = []
    rule = _rule(sent)
    robot = _Robot(Pose2D(4.6, 2.0, 0.0), Path(np.array([[4.6, 2.0], [7.0, 2.0]])))
    rule.tick(0.0, robot)  # type: ignore[arg-type]
    rule.tick(1.0, robot)  # type: ignore[arg-type]
    assert sent == []
    assert rule.waiting_for is None
    assert robot.navigation_stack.navigator.state is NavigationState.RUNNING


def test_a_waiting_robot_whose_new_path_leads_away_goes_on() -> None:
    sent: list[tuple[str, str, m.ZoneRequestType]] = []
    rule = _rule(sent)
    robot = _Robot(Pose2D(4.6, 2.0, np.pi), Path(np.array([[4.6, 2.0], [1.0, 2.0]])))
    rule.tick(0.0, robot)  # type: ignore[arg-type]
    _queued(rule, sent)
    rule.tick(1.0, robot)  # type: ignore[arg-type]
    assert rule.waiting_for == "zone:m/1"
    robot.navigation_stack.navigator.path = Path(np.array([[4.6, 2.0], [7.0, 3.5]]))
    rule.tick(2.0, robot)  # type: ignore[arg-type]
    assert rule.waiting_for is None
    assert robot.navigation_stack.navigator.state is NavigationState.RUNNING
    assert sent[-1][1:] == ("zone:m/1", m.ZoneRequestType.RELEASE)
    # Told on the bus: busy (queued), the wait, and its end without the zone.
    assert [(e.kind, e.zone) for e in robot.published] == [  # type: ignore[attr-defined]
        ("traffic_busy", "zone:m/1"), ("traffic_wait_started", "zone:m/1"),
        ("traffic_wait_ended", "zone:m/1")]
    last = robot.published[-1]
    assert isinstance(last, events.TrafficWaitEnded) and not last.granted


def _told_place(rule: TrafficRule, sent: list[tuple[str, str, m.ZoneRequestType]],
                place: int) -> None:
    rid, zone, _ = sent[0]
    rule.on_response(m.ZoneResponse(header_id=1, serial_number="r1", request_id=rid,
                                    zone_id=zone, grant_type=m.GrantType.QUEUED,
                                    queue_position=place))


def test_a_robot_further_back_in_line_waits_further_back_and_moves_up() -> None:
    # Five robots once stood at a door's mouth waiting for it, walling in the holder that had
    # to come out: each robot not next in line keeps queue_spacing more room per robot ahead.
    sent: list[tuple[str, str, m.ZoneRequestType]] = []
    rule = _rule(sent)
    robot = _Robot(Pose2D(7.9, 2.0, np.pi), Path(np.array([[7.9, 2.0], [1.0, 2.0]])))
    navigator = robot.navigation_stack.navigator
    rule.tick(0.0, robot)  # type: ignore[arg-type]  # the door is 3.1 m ahead: asked for
    _told_place(rule, sent, 1)
    rule.tick(1.0, robot)  # type: ignore[arg-type]
    assert navigator.state is NavigationState.RUNNING  # 1 + 1.5 = 2.5 m is its stop
    robot.pose = Pose2D(7.0, 2.0, np.pi)  # 2.2 m ahead
    rule.tick(2.0, robot)  # type: ignore[arg-type]
    assert rule.waiting_for == "zone:m/1" and navigator.state is NavigationState.PAUSED
    rule.tick(3.0, robot)  # type: ignore[arg-type]
    assert navigator.state is NavigationState.PAUSED  # no one ahead went in yet
    _told_place(rule, sent, 0)  # the robot ahead went in: it moves up
    rule.tick(4.0, robot)  # type: ignore[arg-type]
    assert rule.waiting_for is None and navigator.state is NavigationState.RUNNING
    robot.pose = Pose2D(5.7, 2.0, np.pi)  # 0.9 m ahead: the front stop
    rule.tick(5.0, robot)  # type: ignore[arg-type]
    assert rule.waiting_for == "zone:m/1" and navigator.state is NavigationState.PAUSED
    assert [k for _, _, k in sent] == [m.ZoneRequestType.ACCESS]  # one request throughout
    # One wait told, moving up included (no end and start again for each step up).
    assert [e.kind for e in robot.published] == ["traffic_busy", "traffic_wait_started"]
    rid, zone, _ = sent[0]
    rule.on_response(m.ZoneResponse(header_id=2, serial_number="r1", request_id=rid,
                                    zone_id=zone, grant_type=m.GrantType.GRANTED,
                                    lease_expiry=60.0))
    rule.tick(6.0, robot)  # type: ignore[arg-type]
    assert navigator.state is NavigationState.RUNNING
    last = robot.published[-1]
    assert isinstance(last, events.TrafficWaitEnded) and last.granted
    assert len(robot.published) == 3


def test_a_robot_next_in_line_stops_at_the_stop_distance() -> None:
    sent: list[tuple[str, str, m.ZoneRequestType]] = []
    rule = _rule(sent)
    robot = _Robot(Pose2D(7.0, 2.0, np.pi), Path(np.array([[7.0, 2.0], [1.0, 2.0]])))
    navigator = robot.navigation_stack.navigator
    rule.tick(0.0, robot)  # type: ignore[arg-type]
    _told_place(rule, sent, 0)
    rule.tick(1.0, robot)  # type: ignore[arg-type]
    assert navigator.state is NavigationState.RUNNING  # 2.2 m ahead, its stop is at 1 m
    robot.pose = Pose2D(5.7, 2.0, np.pi)  # 0.9 m ahead
    rule.tick(2.0, robot)  # type: ignore[arg-type]
    assert rule.waiting_for == "zone:m/1" and navigator.state is NavigationState.PAUSED


def test_a_robot_far_back_in_line_stops_where_it_asked() -> None:
    sent: list[tuple[str, str, m.ZoneRequestType]] = []
    rule = _rule(sent)
    robot = _Robot(Pose2D(7.9, 2.0, np.pi), Path(np.array([[7.9, 2.0], [1.0, 2.0]])))
    rule.tick(0.0, robot)  # type: ignore[arg-type]
    _told_place(rule, sent, 5)  # 1 + 5 x 1.5 m is past the lookahead: it stops at once
    rule.tick(1.0, robot)  # type: ignore[arg-type]
    assert rule.waiting_for == "zone:m/1"


def _three_rooms() -> Map:
    """Three rooms in a row (x 0..4, 4.1..7, 7.1..10.1), 1 m doors at y 1.5..2.5."""
    res = 0.05
    occ = np.zeros((int(4.2 / res), int(10.2 / res)), dtype=bool)
    occ[:2, :] = occ[-2:, :] = True
    occ[:, :2] = occ[:, -2:] = True
    for x in (4.05, 7.05):
        col = int(x / res)
        occ[:, col:col + 2] = True
        occ[int(1.5 / res):int(2.5 / res), col:col + 2] = False
    return Map.from_occupied(occ, resolution=res)


def test_a_robot_back_in_line_never_waits_inside_the_zone_it_comes_out_of() -> None:
    # Waiting there it would hold one door while it waits for the next (hold-and-wait).
    sent: list[tuple[str, str, m.ZoneRequestType]] = []

    def send(rid: str, zone: str, kind: m.ZoneRequestType, _duration: float,
             _flow: str | None = None) -> None:
        sent.append((rid, zone, kind))

    rule = TrafficRule("r1", {"m": find_zones("m", _three_rooms())}, TrafficConfig(), send)
    robot = _Robot(Pose2D(3.6, 2.0, 0.0), Path(np.array([[2.0, 2.0], [9.5, 2.0]])))
    navigator = robot.navigation_stack.navigator
    rule.tick(0.0, robot)  # type: ignore[arg-type]  # in door 1's zone, door 2 2.7 m ahead
    # Not yet holding the zone it stands in, it asks for nothing of the next passage.
    assert [zone for _, zone, _ in sent] == ["zone:m/1"]
    rule.on_response(m.ZoneResponse(1, "r1", sent[0][0], "zone:m/1",
                                    m.GrantType.GRANTED, 30.0))
    rule.tick(0.05, robot)  # type: ignore[arg-type]  # a grant: the next check is at once
    ids = {zone: rid for rid, zone, _ in sent}
    assert set(ids) == {"zone:m/1", "zone:m/2"}
    rule.on_response(m.ZoneResponse(2, "r1", ids["zone:m/2"], "zone:m/2",
                                    m.GrantType.QUEUED, queue_position=1))
    robot.pose = Pose2D(4.5, 2.0, 0.0)  # through door 1, 1.9 m from door 2
    rule.tick(1.0, robot)  # type: ignore[arg-type]
    assert navigator.state is NavigationState.RUNNING  # in a zone: its stop stays at 1 m
    assert rule.held == ("zone:m/1",)
    robot.pose = Pose2D(5.0, 2.0, 0.0)  # out of door 1, 1.4 m from door 2
    rule.tick(2.0, robot)  # type: ignore[arg-type]
    assert rule.waiting_for == "zone:m/2" and navigator.state is NavigationState.PAUSED
    assert rule.held == ()  # door 1 given back


def test_a_zone_asked_for_is_kept_while_the_path_to_it_grows_a_little() -> None:
    # Waiting near the lookahead, a robot whose resumed path came out a few centimetres longer
    # gave the zone back on being granted it, and queued again at the back of the line.
    sent: list[tuple[str, str, m.ZoneRequestType]] = []
    rule = _rule(sent)
    robot = _Robot(Pose2D(7.9, 2.0, np.pi), Path(np.array([[7.9, 2.0], [1.0, 2.0]])))
    rule.tick(0.0, robot)  # type: ignore[arg-type]  # 3.1 m ahead: asked for
    _queued(rule, sent)
    navigator = robot.navigation_stack.navigator
    navigator.path = Path(np.array([[7.9, 2.0], [7.9, 2.6], [6.0, 2.6], [6.0, 2.0],
                                    [1.0, 2.0]]))  # a detour: 4.3 m to the door
    rule.tick(1.0, robot)  # type: ignore[arg-type]
    assert [k for _, _, k in sent] == [m.ZoneRequestType.ACCESS]
    navigator.path = Path(np.array([[7.9, 2.0], [7.9, 3.2], [6.0, 3.2], [6.0, 2.0],
                                    [1.0, 2.0]]))  # 5.5 m: well past the lookahead
    rule.tick(2.0, robot)  # type: ignore[arg-type]
    assert [k for _, _, k in sent] == [m.ZoneRequestType.ACCESS, m.ZoneRequestType.RELEASE]


def test_moving_up_in_line_is_one_wait() -> None:
    sent: list[tuple[str, str, m.ZoneRequestType]] = []
    rule = _rule(sent)
    robot = _Robot(Pose2D(7.0, 2.0, np.pi), Path(np.array([[7.0, 2.0], [1.0, 2.0]])))
    rule.tick(0.0, robot)  # type: ignore[arg-type]
    _told_place(rule, sent, 1)
    rule.tick(1.0, robot)  # type: ignore[arg-type]  # 2.2 m ahead: stops
    _told_place(rule, sent, 0)
    rule.tick(2.0, robot)  # type: ignore[arg-type]  # moves up
    robot.pose = Pose2D(5.7, 2.0, np.pi)
    rule.tick(3.0, robot)  # type: ignore[arg-type]  # stops again, at the front
    assert rule.waiting_for == "zone:m/1"
    assert rule.waits == 1


def test_a_request_never_answered_is_asked_again_with_the_same_id() -> None:
    # Zone requests are QoS 0: one sent while the fleet manager was off the broker is lost, and
    # the robot, stopped before the zone, would wait for ever.
    sent: list[tuple[str, str, m.ZoneRequestType]] = []
    rule = _rule(sent)
    robot = _Robot(Pose2D(4.6, 2.0, np.pi), Path(np.array([[4.6, 2.0], [1.0, 2.0]])))
    rule.tick(0.0, robot)  # type: ignore[arg-type]
    rule.tick(4.0, robot)  # type: ignore[arg-type]
    assert len(sent) == 1
    rule.tick(5.2, robot)  # type: ignore[arg-type]
    assert sent[1] == sent[0]
    _queued(rule, sent)  # answered at 5.2: a waiter, the next ask 5 s after that
    rule.tick(10.0, robot)  # type: ignore[arg-type]
    assert len(sent) == 2
    rule.tick(10.4, robot)  # type: ignore[arg-type]
    assert sent[2] == sent[0]  # keeps its place: the lease book takes it as the same ask
    rid, zone, _ = sent[0]
    rule.on_response(m.ZoneResponse(header_id=2, serial_number="r1", request_id=rid,
                                    zone_id=zone, grant_type=m.GrantType.GRANTED,
                                    lease_expiry=40.0))
    rule.tick(20.0, robot)  # type: ignore[arg-type]
    assert len(sent) == 3  # granted: renewed before expiry only
