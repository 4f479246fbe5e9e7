"""Master control: the site's side of the fleet (VDA 5050's name for it).

It owns the :class:`~polynav.leases.book.LeaseBook` of the site's shared resources and talks to
each robot only through messages on a :class:`~polynav.fleet.interface.Transport`:

- it sends **orders** (VDA 5050: a first node where the robot stands, then a node per point to
  go through, an edge between each two) and **instant actions** (cancel);
- it answers **zone requests** from the lease book: ACCESS asks for or renews a lease (GRANTED
  with its expiry, or QUEUED with the waiter's place in line, sent again whenever the place
  changes; a waiter is sent GRANTED when its turn comes, REJECTED when it has waited
  ``max_wait``), RELEASE gives it back; a lease not renewed in time is EXPIRED; an expiry is
  sent on the asking robot's clock when its request says what its clock read;
- it keeps the last **state** of each robot, which ``GET /api/fleet`` shows; a message from a
  robot that breaks its schema is logged and not used.

It listens with one wildcard subscription per kind (``uagv/v2/<manufacturer>/+/state`` and
``.../+/zoneRequest``), made once at construction: the subscriptions do not grow with the
fleet (a thousand robots are two filters, not two thousand topics), and a robot not known at
start is heard. The sender is the topic's serial number; a message whose own
manufacturer or serial number disagrees with its topic is dropped (logged once per topic and
kind: a misconfigured robot must not speak for another, nor flood the log). A robot first
heard by its state or a zone request is adopted (as the fleet manager adopts one announced by
its ``connection``, docs/decisions.md); :meth:`MasterControl.take_adopted` says which.

Its messages carry VDA 5050 headers of ``version`` from ``manufacturer`` (one fleet of one
manufacturer's vehicles), stamped on the site's clock.

It runs on the site's clock: :meth:`MasterControl.tick` is called between physics steps.
"""

from __future__ import annotations

import datetime as dt
import itertools
import logging
import math
from dataclasses import dataclass

from polynav.errors import InvalidRequest, PolynavError
from polynav.fleet import messages as m
from polynav.fleet.interface import Inbox, Transport
from polynav.geometry import Pose2D
from polynav.leases.book import LeaseBook, LeaseEventKind

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True)
class Stop:
    """One stop of an order: a named point on a map, and its pose (for the order's node)."""

    point: str
    map_name: str
    pose: Pose2D


@dataclass(slots=True)
class _Robot:
    state: m.State | None = None
    state_at: float | None = None
    order_count: int = 0
    clock_offset: float = 0.0  # the robot's site time minus ours [s], from its zone requests
    last_order: m.Order | None = None
    offline: bool = False


class MasterControl:
    """The fleet's master control (see the module docstring).

    Args:
        transport: where the robots are.
        leases: the site's lease book.
        version: the VDA 5050 version spoken (``"2.0.0"`` or ``"2.1.0"``).
        manufacturer: the robots' manufacturer, the third level of their topics.
        epoch: the UTC moment site time 0 stands for (headers' timestamps); now by default.
    """

    def __init__(self, transport: Transport, leases: LeaseBook | None = None, *,
                 version: str = m.DEFAULT_VERSION, manufacturer: str = m.DEFAULT_MANUFACTURER,
                 epoch: dt.datetime | None = None) -> None:
        self.transport = transport
        self.leases = leases or LeaseBook()
        self.manufacturer = manufacturer
        self._robots: dict[str, _Robot] = {}
        self._now = 0.0
        self._vda_headers = m.Headers(version, manufacturer, lambda: self._now, epoch)
        self._headers = itertools.count(1)
        # The request id each (zone, robot) was last asked with: a grant that comes later (the
        # waiter's turn) answers that request.
        self._request_ids: dict[tuple[str, str], str] = {}
        # The (request id, place in line) each waiter was last told, so a place is sent once
        # each time it changes.
        self._told_places: dict[tuple[str, str], tuple[str, int]] = {}
        self.zone_requests = 0
        self.mismatched = 0  # messages dropped: their header disagreed with their topic
        self._mismatch_said: set[tuple[str, str]] = set()
        self._adopted: list[str] = []
        self._states: Inbox = transport.subscribe(self._topic("+", m.State))
        self._zone_requests: Inbox = transport.subscribe(self._topic("+", m.ZoneRequest))

    def add_robot(self, serial_number: str) -> None:
        """Take a robot into the fleet (its state and zone requests are heard through the
        wildcard subscriptions whether or not it is added; see the module docstring).

        Raises:
            InvalidRequest: an empty or already known serial number.
        """
        if not serial_number or serial_number in self._robots:
            raise InvalidRequest("serial_number", f"{serial_number!r} is empty or known")
        self._robots[serial_number] = _Robot()

    def knows(self, serial_number: str) -> bool:
        """Whether ``serial_number`` is in the fleet (added, or adopted when first heard)."""
        return serial_number in self._robots

    def take_adopted(self) -> list[str]:
        """The robots adopted since the last call, first heard by a state or a zone request
        rather than added, in the order they were heard."""
        adopted, self._adopted = self._adopted, []
        return adopted

    def set_online(self, serial_number: str, online: bool) -> None:
        """Whether the robot's connection is up; an offline robot's zone requests are
        rejected (the fleet manager revokes its leases when its last will arrives).

        Raises:
            InvalidRequest: an unknown robot.
        """
        self._robot(serial_number).offline = not online

    @property
    def robots(self) -> tuple[str, ...]:
        return tuple(self._robots)

    def state(self, serial_number: str) -> m.State | None:
        """The robot's last state, ``None`` before its first."""
        return self._robot(serial_number).state

    def state_time(self, serial_number: str) -> float | None:
        """When [s of site time] the robot's last state was read, ``None`` before its first."""
        return self._robot(serial_number).state_at

    def send_order(self, serial_number: str, stops: list[Stop], *,
                   order_id: str | None = None) -> str:
        """Send the robot an order through ``stops``; returns the order id (``order_id``, or
        ``<serial>-<n>``: a fleet manager that may restart names its orders itself, since a
        robot ignores an order whose id and update id it has already had).

        The order's first node is where the robot stands (its last state's position, named by
        its last node, VDA 5050 §6.6.1: a new order starts where the vehicle is), then one node
        per stop, all released, with an edge between each two.

        Raises:
            InvalidRequest: an unknown robot, no stops, or a robot whose position is not known
                yet (no state, or a state without a position).
        """
        robot = self._robot(serial_number)
        if not stops:
            raise InvalidRequest("stops", "an order needs at least one stop")
        here = robot.state.agv_position if robot.state is not None else None
        if here is None:
            raise InvalidRequest("robot", f"{serial_number} has not said where it is yet")
        robot.order_count += 1
        if order_id is None:
            order_id = f"{serial_number}-{robot.order_count}"
        elif not order_id:
            raise InvalidRequest("order_id", "must not be empty")
        start = robot.state.last_node_id if robot.state and robot.state.last_node_id else (
            f"{serial_number}-here")
        nodes = [m.Node(start, 0, m.NodePosition(here.x, here.y, _angle(here.theta), here.map_id))]
        nodes += [
            m.Node(stop.point, 2 * k, m.NodePosition(stop.pose.x, stop.pose.y,
                                                     _angle(stop.pose.theta), stop.map_name))
            for k, stop in enumerate(stops, start=1)]
        edges = tuple(
            m.Edge(f"{a.node_id}->{b.node_id}", a.sequence_id + 1, a.node_id, b.node_id)
            for a, b in itertools.pairwise(nodes))
        order = m.Order(self._vda_headers.stamp(serial_number, m.Order), order_id, 0,
                        tuple(nodes), edges)
        self.transport.publish(self._topic(serial_number, m.Order), order)
        robot.last_order = order
        log.info("order %s to %s: %s", order_id, serial_number, [s.point for s in stops])
        return order_id

    def resend_order(self, serial_number: str, order_id: str) -> bool:
        """Send the robot's last order again, unchanged (same orderId and orderUpdateId, so a
        robot that had it ignores it, VDA 5050 §6.6.2: orders travel at QoS 0 and may be
        lost); False if its last order is not ``order_id``.

        Raises:
            InvalidRequest: an unknown robot.
        """
        robot = self._robot(serial_number)
        order = robot.last_order
        if order is None or order.order_id != order_id:
            return False
        self.transport.publish(self._topic(serial_number, m.Order), order)
        log.info("order %s re-sent to %s", order_id, serial_number)
        return True

    def request_state(self, serial_number: str) -> None:
        """Ask the robot for its state now (the stateRequest instant action).

        Raises:
            InvalidRequest: an unknown robot.
        """
        self._instant(serial_number, m.ActionType.STATE_REQUEST, "state")

    def cancel_order(self, serial_number: str) -> None:
        """Tell the robot to cancel its order.

        Raises:
            InvalidRequest: an unknown robot.
        """
        self._instant(serial_number, m.ActionType.CANCEL_ORDER, "cancel")

    def _instant(self, serial_number: str, kind: m.ActionType, name: str) -> None:
        self._robot(serial_number)
        header = self._vda_headers.stamp(serial_number, m.InstantActions)
        action = m.Action(f"{name}-{header.header_id}", kind.value)
        self.transport.publish(self._topic(serial_number, m.InstantActions),
                               m.InstantActions(header, (action,)))

    def tick(self, now: float) -> None:
        """Read states and zone requests, answer them, and tell robots what the lease book did."""
        self._now = now
        for topic, state in self._states.drain_topics():
            serial = self._sender(topic, state)
            if serial is None:
                continue
            if isinstance(state, m.State):
                robot = self._robots[serial]
                robot.state, robot.state_at = state, now
            else:
                log.warning("a state of %s not used: %s", serial, state)
        for topic, request in self._zone_requests.drain_topics():
            serial = self._sender(topic, request)
            if serial is None:
                continue
            if not isinstance(request, m.ZoneRequest):
                log.warning("a zone request of %s not used: %s", serial, request)
            elif self._robots[serial].offline:
                # Sent before its connection was lost, read after: the leases it had are
                # revoked, and it gets none while away.
                log.warning("zone request %s of %s refused: it is offline",
                            request.request_id, serial)
                self._respond(serial, request.request_id, request.zone_id,
                              m.GrantType.REJECTED, None)
            else:
                self._answer(serial, request, now)
        self.leases.tick(now)
        self.answer_lease_changes()

    def answer_lease_changes(self) -> None:
        """Tell robots what the lease book did since the last call (grants to waiters,
        expiries, places in line); :meth:`tick` does, and so may one who changed the book
        between ticks (leases revoked from a lost robot go at once to those waiting)."""
        self._forward_events()
        self._tell_places()

    def _answer(self, serial: str, request: m.ZoneRequest, now: float) -> None:
        self.zone_requests += 1
        if request.sent_at is not None and math.isfinite(request.sent_at):
            # Its clock, not ours, judges its lease: answer expiries on it (the message's
            # transit makes the robot's expiry a little later than ours, by milliseconds,
            # against the seconds it renews ahead).
            self._robots[serial].clock_offset = request.sent_at - now
        zone = request.zone_id
        key = (zone, serial)
        if request.request_type is m.ZoneRequestType.RELEASE:
            self.leases.release(zone, serial, now=now)
            self._request_ids.pop(key, None)
            return
        self._request_ids[key] = request.request_id
        try:
            if self.leases.lease(zone, serial) is None:
                # A grant, now or when the robot's turn comes, is answered from the book's
                # GRANTED event (see _forward_events), so it is answered once.
                # A waiter is answered QUEUED, with its place, by _tell_places; forgetting what
                # it was told makes that answer come for every request, a repeated one too.
                self._told_places.pop(key, None)
                self.leases.request(zone, serial, now=now, duration=request.duration,
                                    flow=request.flow)
                return
            lease = self.leases.renew(zone, serial, now=now, duration=request.duration)
        except PolynavError as exc:
            log.warning("zone request %s of %s refused: %s", request.request_id, serial, exc)
            self._respond(serial, request.request_id, zone, m.GrantType.REVOKED, None)
            self.leases.release(zone, serial, now=now)
            return
        self._respond(serial, request.request_id, zone, m.GrantType.GRANTED, lease.expires_at)

    def _forward_events(self) -> None:
        for event in self.leases.take_events():
            key = (event.resource, event.holder)
            request_id = self._request_ids.get(key)
            if request_id is None or event.holder not in self._robots:
                continue
            if event.kind is LeaseEventKind.GRANTED and event.lease is not None:
                self._respond(event.holder, request_id, event.resource, m.GrantType.GRANTED,
                              event.lease.expires_at)
            elif event.kind is LeaseEventKind.EXPIRED:
                self._request_ids.pop(key, None)
                self._respond(event.holder, request_id, event.resource, m.GrantType.EXPIRED,
                              None)
            elif event.kind is LeaseEventKind.WAIT_TIMED_OUT:
                self._request_ids.pop(key, None)
                self._respond(event.holder, request_id, event.resource, m.GrantType.REJECTED,
                              None)

    def _tell_places(self) -> None:
        """Send each waiter QUEUED with its place in line when it is new or has changed: a robot
        further back waits further from the zone, leaving its mouth clear for whoever comes out
        (:mod:`polynav.fleet.traffic`)."""
        waiting: set[tuple[str, str]] = set()
        for zone, queue in self.leases.queues().items():
            for place, waiter in enumerate(queue):
                key = (zone, waiter.holder)
                request_id = self._request_ids.get(key)
                if request_id is None or waiter.holder not in self._robots:
                    continue
                waiting.add(key)
                if self._told_places.get(key) != (request_id, place):
                    self._told_places[key] = (request_id, place)
                    self._respond(waiter.holder, request_id, zone, m.GrantType.QUEUED, None,
                                  place)
        for key in self._told_places.keys() - waiting:
            del self._told_places[key]

    def _respond(self, serial: str, request_id: str, zone: str, grant: m.GrantType,
                 expiry: float | None, place: int | None = None) -> None:
        if expiry is not None:
            expiry += self._robots[serial].clock_offset
        self.transport.publish(
            self._topic(serial, m.ZoneResponse),
            m.ZoneResponse(next(self._headers), serial, request_id, zone, grant, expiry, place))

    def _sender(self, topic: str, message: m.Received) -> str | None:
        """The robot that sent ``message`` on ``topic``: the topic's serial number, adopted if
        new (a :class:`~polynav.fleet.messages.Rejected` adopts no one: its caller logs it);
        None (dropped, logged once per topic and kind) if the topic is not a vehicle's of this
        manufacturer or the message's header names another vehicle."""
        levels = topic.split("/")
        serial = levels[3] if len(levels) == 5 else ""
        kind = levels[-1]
        if (not serial or levels[:3] != [m.INTERFACE, m.MAJOR, self.manufacturer]
                or "+" in serial or "#" in serial):
            self._mismatch(topic, kind, f"not a vehicle topic of {self.manufacturer}")
            return None
        said: tuple[str, str] | None = None
        if isinstance(message, m.State):
            said = (message.header.manufacturer, message.header.serial_number)
        elif isinstance(message, m.ZoneRequest):
            said = (self.manufacturer, message.serial_number)
        if said is not None and said != (self.manufacturer, serial):
            self._mismatch(topic, kind, f"its header is of {said[0]}/{said[1]}")
            return None
        if serial not in self._robots and not isinstance(message, m.Rejected):
            self._robots[serial] = _Robot()
            self._adopted.append(serial)
            log.info("robot %s adopted: first heard by its %s", serial, kind)
        return serial

    def _mismatch(self, topic: str, kind: str, why: str) -> None:
        self.mismatched += 1
        key = (topic, kind)
        if key in self._mismatch_said:
            log.debug("a %s on %s dropped: %s", kind, topic, why)
            return
        self._mismatch_said.add(key)
        log.warning("a %s on %s dropped: %s (further ones on this topic are dropped "
                    "silently)", kind, topic, why)

    def _topic(self, serial_number: str, kind: type) -> str:
        return m.topic(serial_number, kind, self.manufacturer)

    def _robot(self, serial_number: str) -> _Robot:
        robot = self._robots.get(serial_number)
        if robot is None:
            raise InvalidRequest("robot", f"no robot {serial_number!r} in the fleet")
        return robot


def _angle(theta: float) -> float:
    """``theta`` in [-pi, pi], as the order schema wants it."""
    return math.atan2(math.sin(theta), math.cos(theta))
