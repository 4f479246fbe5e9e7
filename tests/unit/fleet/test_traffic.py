"""One robot's side of the traffic rule: what it asks for, when it stops, when it may go."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from polynav.fleet import messages as m
from polynav.fleet.traffic import TrafficConfig, TrafficRule
from polynav.fleet.zones import find_zones
from polynav.geometry import Pose2D
from polynav.leases.book import LeaseBook, LeaseEventKind
from polynav.maps.map import Map
from polynav.nav.attempt import NavigationState
from polynav.planning.path import Path
from polynav.runtime import events
from tests.unit.fleet.test_zones import _long_corridor, _two_rooms


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

    def pause(self, *, make_way: bool = False) -> None:
        self.make_way = make_way
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


class _Fleet:
    """The fleet's side of the zone requests for a few rules, on a real lease book: answers
    go out after each round of ticks, as over a transport."""

    def __init__(self) -> None:
        self.book = LeaseBook()
        self.rules: dict[str, TrafficRule] = {}
        self.now = 0.0
        self._ids: dict[tuple[str, str], str] = {}
        self._outbox: list[tuple[str, m.ZoneResponse]] = []
        self._told: dict[tuple[str, str], int] = {}

    def sender(self, holder: str) -> Callable[..., None]:
        def send(rid: str, zone: str, kind: m.ZoneRequestType, duration: float,
                 flow: str | None = None) -> None:
            if kind is m.ZoneRequestType.RELEASE:
                self.book.release(zone, holder, now=self.now)
                self._ids.pop((zone, holder), None)
                self._told.pop((zone, holder), None)
                return
            self._ids[(zone, holder)] = rid
            if self.book.lease(zone, holder) is None:
                self.book.request(zone, holder, now=self.now, duration=duration, flow=flow)
            else:
                lease = self.book.renew(zone, holder, now=self.now, duration=duration)
                self._answer(holder, zone, m.GrantType.GRANTED, lease.expires_at)
        return send

    def _answer(self, holder: str, zone: str, grant: m.GrantType, expiry: float | None = None,
                place: int | None = None) -> None:
        rid = self._ids.get((zone, holder))
        if rid is not None:
            self._outbox.append((holder, m.ZoneResponse(1, holder, rid, zone, grant, expiry,
                                                        place)))

    def deliver(self) -> None:
        self.book.tick(self.now)
        for event in self.book.take_events():
            if event.kind is LeaseEventKind.GRANTED and event.lease is not None:
                self._answer(event.holder, event.resource, m.GrantType.GRANTED,
                             event.lease.expires_at)
        for zone, queue in self.book.queues().items():
            for place, waiter in enumerate(queue):
                if self._told.get((zone, waiter.holder)) != place:
                    self._told[(zone, waiter.holder)] = place
                    self._answer(waiter.holder, zone, m.GrantType.QUEUED, place=place)
        out, self._outbox = self._outbox, []
        for holder, response in out:
            self.rules[holder].on_response(response)


def _advance(robot: _Robot, distance: float) -> None:
    """Move ``robot`` ``distance`` [m] on along its path (it drives through other robots: the
    rule, not the bodies, is under test)."""
    points = robot.path.points
    x, y = robot.pose.x, robot.pose.y
    for a, b in zip(points[:-1], points[1:], strict=True):
        d = b - a
        t = float(np.clip(np.dot([x, y] - a, d) / np.dot(d, d), 0.0, 1.0))
        if np.hypot(*(a + t * d - [x, y])) < 1e-6 and t < 1.0:
            left = float(np.hypot(*d)) * (1.0 - t)
            if distance < left:
                p = a + t * d + d / np.hypot(*d) * distance
                robot.pose = Pose2D(float(p[0]), float(p[1]), 0.0)
                return
            distance -= left
            x, y = float(b[0]), float(b[1])
    robot.pose = Pose2D(float(points[-1][0]), float(points[-1][1]), 0.0)
    robot.navigation_stack.navigator.state = NavigationState.SUCCEEDED


def test_robots_on_a_long_corridor_get_through_and_use_its_segments_at_once() -> None:
    # Four robots start together: two the whole corridor's length, opposite ways, and two
    # short ways at its ends, against the long one that comes their way. Asking in path
    # order, the two long ones could each hold the end segment the other waits for; in
    # ascending zone order no one waits on a robot that waits on it.
    zones = {"m": find_zones("m", _long_corridor())}
    zmap = zones["m"]
    ways = {
        "east": [(2.0, 2.0), (2.0, 4.5), (22.0, 4.5), (22.0, 2.0)],
        "short_east": [(6.0, 2.3), (6.0, 4.5), (2.0, 4.5), (2.0, 2.3)],
        "west": [(22.0, 2.0), (22.0, 4.5), (2.0, 4.5), (2.0, 2.0)],
        "short_west": [(18.0, 2.3), (18.0, 4.5), (22.0, 4.5), (22.0, 2.3)],
    }  # asking in this order: "short_east" is in line for the west end before "west"
    fleet = _Fleet()
    robots = {}
    for name, way in ways.items():
        robots[name] = _Robot(Pose2D(*way[0], 0.0), Path(np.array(way)))
        fleet.rules[name] = TrafficRule(name, zones, TrafficConfig(), fleet.sender(name))
    both_ends_busy = False
    while fleet.now < 300.0 and not all(
            r.navigation_stack.navigator.state is NavigationState.SUCCEEDED
            for r in robots.values()):
        for name, robot in robots.items():
            fleet.rules[name].tick(fleet.now, robot)  # type: ignore[arg-type]
        fleet.deliver()
        for name, robot in robots.items():
            if robot.navigation_stack.navigator.state is NavigationState.RUNNING:
                _advance(robot, 0.1)
                zone = zmap.zone_at(robot.pose.x, robot.pose.y)
                if zone and robot.navigation_stack.navigator.state is NavigationState.RUNNING:
                    assert zmap.zone_id(zone) in fleet.rules[name].held, (name, robot.pose)
        inside = {n for n, r in robots.items()
                  if r.navigation_stack.navigator.state is NavigationState.RUNNING
                  and zmap.zone_at(r.pose.x, 4.5) and 4.0 < r.pose.y < 5.0}
        both_ends_busy |= bool(inside & {"east", "short_west"}) and bool(
            inside & {"west", "short_east"})
        fleet.now = round(fleet.now + 0.1, 1)
    assert all(r.navigation_stack.navigator.state is NavigationState.SUCCEEDED
               for r in robots.values()), {n: r.pose for n, r in robots.items()}
    # Robots going opposite ways were in the corridor at once (on segments apart): with one
    # zone for the corridor, one way would have had to drain before the other went in.
    assert both_ends_busy
    assert fleet.book.resources() == () or all(
        not fleet.book.leases(z) for z in fleet.book.resources())


def test_segments_ahead_are_kept_while_the_path_is_away_a_moment_not_longer() -> None:
    # Between two plans (no path) the robot needs only the segment it stands in; giving the
    # rest back at once let a waiter take them, and the robot, standing in the corridor,
    # waited behind it (bench fleet seeds 0 and 3). Kept for release_grace, then given back.
    zones = {"m": find_zones("m", _long_corridor())}
    fleet = _Fleet()
    robot = _Robot(Pose2D(3.0, 4.5, 0.0), Path(np.array([(3.0, 4.5), (22.0, 4.5), (22.0, 2.0)])))
    config = TrafficConfig(release_grace=2.0)
    rule = fleet.rules["r1"] = TrafficRule("r1", zones, config, fleet.sender("r1"))
    for _ in range(20):
        rule.tick(fleet.now, robot)  # type: ignore[arg-type]
        fleet.deliver()
        fleet.now = round(fleet.now + 0.2, 1)
    held = rule.held
    assert len(held) >= 3 and all(fleet.book.lease(z, "r1") is not None for z in held)
    robot.navigation_stack.navigator.path = None  # type: ignore[assignment]
    here = zones["m"].zone_id(zones["m"].zone_at(3.0, 4.5))
    start = fleet.now
    while fleet.now - start < config.release_grace - 0.3:
        rule.tick(fleet.now, robot)  # type: ignore[arg-type]
        fleet.deliver()
        assert rule.held == held
        fleet.now = round(fleet.now + 0.2, 1)
    robot.navigation_stack.navigator.path = robot.path  # the next plan: the same way
    rule.tick(fleet.now, robot)  # type: ignore[arg-type]
    assert rule.held == held
    robot.navigation_stack.navigator.path = None  # type: ignore[assignment]
    start = fleet.now
    while fleet.now - start < config.release_grace + 0.5:
        rule.tick(fleet.now, robot)  # type: ignore[arg-type]
        fleet.deliver()
        fleet.now = round(fleet.now + 0.2, 1)
    assert rule.held == (here,)
    assert [z for z in held if fleet.book.lease(z, "r1") is not None] == [here]


def test_a_segment_behind_is_kept_while_near_so_a_way_back_into_it_keeps_all() -> None:
    # Bench fleet seed 2: a robot driving east gave back the segment behind it as its centre
    # left it; its path round two robots (or a step aside for a walker) took it back into it,
    # it stood there holding nothing, asked for it again and gave back the segments ahead as
    # out of order. Kept while near, the way back into it finds every segment still held.
    zones = {"m": find_zones("m", _long_corridor())}
    zmap = zones["m"]
    fleet = _Fleet()
    robot = _Robot(Pose2D(3.0, 4.5, 0.0), Path(np.array([(3.0, 4.5), (16.0, 4.5)])))
    config = TrafficConfig(release_grace=2.0, keep_behind=2.5)
    rule = fleet.rules["r1"] = TrafficRule("r1", zones, config, fleet.sender("r1"))
    behind = zmap.zone_id(zmap.zone_at(11.5, 4.5))
    ahead = zmap.zone_id(zmap.zone_at(12.5, 4.5))
    assert behind != ahead
    boundary = min(x for x in np.arange(11.5, 12.5, 0.05) if zmap.zone_at(x, 4.5)
                   == zmap.zone_at(12.5, 4.5))

    def run(seconds: float, speed: float = 0.0) -> None:
        start = fleet.now
        while fleet.now - start < seconds:
            rule.tick(fleet.now, robot)  # type: ignore[arg-type]
            fleet.deliver()
            if speed:
                _advance(robot, speed * 0.2)
            fleet.now = round(fleet.now + 0.2, 1)

    run(1.0)
    while robot.pose.x < boundary + 0.3:  # drive on to just past the boundary
        run(0.2, speed=0.5)
    run(config.release_grace + 1.0)  # standing there, past the grace
    assert {behind, ahead} <= set(rule.held)
    # The next plan goes back a metre and a half round someone, then east again.
    x = robot.pose.x
    robot.navigation_stack.navigator.path = Path(np.array([(x, 4.5), (x - 1.5, 4.6),
                                                           (16.0, 4.5)]))
    robot.path = robot.navigation_stack.navigator.path
    run(1.0)
    assert {behind, ahead} <= set(rule.held)
    assert all(fleet.book.lease(z, "r1") is not None for z in (behind, ahead))
    # Once it is keep_behind past the segment behind, and the grace is over, it goes back.
    while robot.pose.x < boundary + config.keep_behind + 0.1:
        run(0.2, speed=0.5)
    run(config.release_grace + 0.5)
    assert behind not in rule.held and fleet.book.lease(behind, "r1") is None
    assert ahead in rule.held
