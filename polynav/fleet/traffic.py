"""The traffic rule: one robot at a time in each narrow passage, granted as a lease.

The rule, as one robot keeps it (docs/fleet.md has it for operators):

1. While a goal runs, the robot looks ``lookahead`` metres along its path. The first passage
   (:mod:`polynav.fleet.zones`) it would enter is asked for from the fleet, and so is the one
   it stands in: each zone (segment) of the passage its path crosses, by a VDA 5050 zone
   request with the way it goes through (robots going the same way may share a zone), one at
   a time in ascending zone number, the next once the one before is granted.
2. If the passage ahead is not all granted by the time the robot is ``stop_distance`` from it, the
   robot stops there (its goal is paused) and waits; a robot told it is not next in line stops
   ``queue_spacing`` further back for each robot ahead of it (unless it stands in a zone
   there), and moves up as those ahead go in, so the waiters do not crowd the mouth of the zone
   the holder must come out of. A robot whose goal starts inside a zone it does not hold waits
   where it stands, unless its path leaves that zone within ``leave_within`` metres: a robot at
   a zone's edge on its way out frees the mouth the holder must come out of (waiting there,
   five robots once walled the holder in). One with no path (its plans fail while people
   stand in the way, and it waits for them) is not paused for the zone it stands in: it has no
   way through the passage to hold back, and paused, it stopped giving way (floor 2's room
   door: backed out of the room's zone into the corridor's, it stood frozen in the doorway,
   the walker it was giving way to could not get out, and the robot behind it, holding the
   corridor, waited for the walker). Granted, it goes on.
3. Inside, it renews the lease before it runs out; once the zone is neither ahead nor within
   ``keep_behind`` of it, it gives it back. A robot whose goal has ended (arrived, failed,
   canceled) holds nothing, even where it stands: a parked robot is an obstacle to plan
   round, not a lock.
4. No one waits for ever: the fleet answers a wait longer than its ``max_wait`` with REJECTED;
   the robot then re-plans and asks again (at once, so it keeps its place by when it first
   asked), and a holder cannot keep a zone past ``max_hold`` while others wait
   (:mod:`polynav.leases.book`).

The robot tells what it meets on its runtime's bus, for the dialects' notices: a passage held by
another (:class:`~polynav.runtime.events.TrafficBusy`, when the fleet queues it) and the wait in
front of it, from the first stop until it goes in or no longer needs it
(:class:`~polynav.runtime.events.TrafficWaitStarted`, ``TrafficWaitEnded``).

A robot waiting holds only segments of the passage it waits for, numbered below the one it
waits for (it never stops for a passage while it stands in another: passages are further apart
than a stop distance); one that holds all of its way waits for no lease. So every chain of
waits climbs the zone numbers and cannot close into a cycle: the hold-and-wait deadlock
cannot form (docs/fleet.md, "Why no deadlock").
"""

from __future__ import annotations

import itertools
import logging
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Protocol

from polynav.errors import ConfigError, PolynavError, check_positive
from polynav.fleet import messages as m
from polynav.fleet.zones import ZoneMap, ZoneRun
from polynav.nav.attempt import NavigationState
from polynav.planning.path import Path
from polynav.runtime import events

if TYPE_CHECKING:
    from polynav.runtime.robot_runtime import RobotRuntime

log = logging.getLogger(__name__)

_KEY = "fleet.traffic."

class SendRequest(Protocol):
    """Send a zone request: request id, zone id, type, duration [s], and the way through."""

    def __call__(self, request_id: str, zone_id: str, request_type: m.ZoneRequestType,
                 duration: float, flow: str | None = None) -> None: ...


@dataclass(frozen=True, slots=True)
class TrafficConfig:
    """Distances and timings of the traffic rule.

    Attributes:
        lookahead: how far along the path a zone is asked for [m].
        stop_distance: a robot without the lease stops this far before the zone [m].
        lease_duration: each grant or renewal lasts this long [s].
        renew_before: a lease is renewed when less than this is left of it [s].
        check_period: how often the rule looks at the path [s].
        leave_within: a robot in a zone it does not hold, whose path is out of it within this
            distance [m], is leaving it: it needs no lease and does not wait.
        queue_spacing: a waiter stops this much further back per robot ahead of it in line [m]
            (never further than ``lookahead``, where it asked).
        keep_margin: a zone asked for stays asked for until it is this much beyond
            ``lookahead`` [m]: a robot waiting near the lookahead whose resumed path came out a
            few centimetres longer gave the zone back on being granted it, and queued again at
            the back.
        release_grace: a zone held while the goal runs is given back only once the path has not
            needed it for this long [s]. A path changes for a moment (a re-plan round a
            walker; no path at all between two plans): a robot going west through floor 1's
            corridor gave back the far segments for one check, a robot waiting for them took
            them at once, and the first, standing in the corridor, waited behind it for the
            rest of its mission (bench fleet seeds 0 and 3).
        reask_after: a request not granted is asked again (same id: a waiter keeps its place)
            when no answer came for this long [s]. Zone requests travel at QoS 0: one sent
            while the fleet manager was off the broker (it comes back after the robot) is lost,
            and the robot would wait for an answer that never comes.
        keep_behind: a held segment of a passage the robot is in is kept while it is this
            close [m]: its body, and the way back a step aside for a walker (up to 2 m,
            :mod:`polynav.nav.people_wait`) or a back-up takes it. Bench fleet seed 2, twice: a
            robot gave back the segment behind it, giving way (or its path round two robots)
            took it back into it, and it stood there holding nothing; asking for it again, it
            gave back the segments ahead as out of order (a waiter holds none above the one it
            waits for), and the robots granted those drove up against it.
    """

    lookahead: float = 4.0
    stop_distance: float = 1.0
    lease_duration: float = 30.0
    renew_before: float = 10.0
    check_period: float = 0.2
    leave_within: float = 1.5
    queue_spacing: float = 1.5
    keep_margin: float = 1.0
    release_grace: float = 2.0
    reask_after: float = 5.0
    keep_behind: float = 2.5

    def __post_init__(self) -> None:
        check_positive(self, _KEY, ("lookahead", "stop_distance", "lease_duration",
                                    "renew_before", "check_period", "leave_within",
                                    "queue_spacing", "keep_margin", "release_grace",
                                    "reask_after", "keep_behind"))
        if self.stop_distance >= self.lookahead:
            raise ConfigError(_KEY + "stop_distance", "must be shorter than lookahead")
        if self.renew_before >= self.lease_duration:
            raise ConfigError(_KEY + "renew_before", "must be shorter than lease_duration")


@dataclass(slots=True)
class _ZoneLease:
    request_id: str
    granted: bool = False
    queued: bool = False
    place: int = 0
    expiry: float = -math.inf
    renew_sent: float = -math.inf
    flow: str | None = None
    heard: float = -math.inf  # when it was last asked for or answered [s]
    needed: float = -math.inf  # when the path last needed it [s]
    passage: int = 0  # the zone group it belongs to
    number: int = 0  # its zone number


_NONE = _ZoneLease("")


@dataclass(frozen=True, slots=True)
class _Run:
    """A passage on the robot's path (:class:`~polynav.fleet.zones.ZoneRun`) by zone ids."""

    zones: tuple[str, ...]  # in path order
    numbers: tuple[int, ...]
    group: int
    entry: float
    entries: tuple[float, ...]
    ordered: tuple[str, ...]  # in ascending zone number: the order they are asked for in

    @classmethod
    def of(cls, zmap: ZoneMap, run: ZoneRun) -> _Run:
        zones = tuple(zmap.zone_id(n) for n in run.segments)
        number = dict(zip(zones, run.segments, strict=True))
        return cls(zones, run.segments, run.group, run.entry, run.entries,
                   tuple(sorted(zones, key=number.__getitem__)))

    def number(self, zone_id: str) -> int:
        """The zone number of ``zone_id``, one of the run's zones."""
        return self.numbers[self.zones.index(zone_id)]


@dataclass(frozen=True, slots=True)
class _Plan:
    """What the robot needs this tick: the zones with their flows (None: asked already or no
    clear way), the passage it stands in and the next one ahead, whether it stands in any
    zone (even one it is leaving), and the zones within ``keep_behind`` of it."""

    needed: dict[str, str | None] = field(default_factory=dict)
    inside: _Run | None = None
    ahead: _Run | None = None
    in_zone: bool = False
    active: bool = False  # a goal runs (or stands paused): its path may be between plans
    routed: bool = False  # it has a path (not between plans, nor waiting for people to let one)
    near: frozenset[str] = frozenset()

    @property
    def passages(self) -> set[int]:
        """The zone groups of the passages it needs."""
        return {run.group for run in (self.inside, self.ahead) if run is not None}


class TrafficRule:
    """One robot's side of the traffic rule (see the module docstring)."""

    def __init__(self, holder: str, zones: dict[str, ZoneMap], config: TrafficConfig,
                 send: SendRequest) -> None:
        self.holder = holder
        self.config = config
        self._zones = zones
        self._send = send
        self._leases: dict[str, _ZoneLease] = {}
        self._requests = itertools.count(1)
        self._paused_for: str | None = None
        self._next_check = -math.inf
        self._now = -math.inf  # the time of the last tick: answers are stamped with it
        self.waits = 0
        self.rejections = 0
        self.wait_time = 0.0
        self._wait_started = 0.0
        # The zone it was resumed to move up in line for: its next stop for it is the same wait.
        self._moving_up_for: str | None = None
        # The zone of the wait told on the bus (moving up in line is the same wait), and the
        # zones told busy (queued) while the robot still needs them.
        self._congested: str | None = None
        self._told_busy: set[str] = set()
        # The zones of the passage it got all of and drives through (it stops for none of
        # them again).
        self._entered: set[str] = set()

    @property
    def waiting_for(self) -> str | None:
        """The zone the robot stands waiting for, if any."""
        return self._paused_for

    @property
    def held(self) -> tuple[str, ...]:
        """The zones granted to the robot, sorted."""
        return tuple(sorted(z for z, lease in self._leases.items() if lease.granted))

    def on_response(self, response: m.ZoneResponse) -> None:
        """Take in the fleet's answer to a zone request."""
        lease = self._leases.get(response.zone_id)
        if lease is None or lease.request_id != response.request_id:
            return  # an answer to a request given up since
        grant = response.grant_type
        lease.heard = self._now
        if grant is m.GrantType.GRANTED:
            if not lease.granted:
                self._next_check = -math.inf  # the next zone of its passage is asked at once
            lease.granted, lease.queued = True, False
            lease.expiry = response.lease_expiry if response.lease_expiry is not None else (
                math.inf)
        elif grant is m.GrantType.QUEUED:
            lease.granted, lease.queued = False, True
            lease.place = max(response.queue_position or 0, 0)
        elif grant in (m.GrantType.REJECTED, m.GrantType.REVOKED, m.GrantType.EXPIRED):
            # Lost or waited too long: forget it, and the next check asks again (a waiter
            # asking again at once keeps its place in the queue).
            if grant is m.GrantType.REJECTED:
                self.rejections += 1
                log.warning("%s: gave up waiting for %s; asking again", self.holder,
                            response.zone_id)
            else:
                log.warning("%s: lease on %s %s", self.holder, response.zone_id, grant.value)
            del self._leases[response.zone_id]

    def resend(self) -> None:
        """Ask again for every zone asked for or held, with the same request ids: after the
        link to the fleet was lost, a request or its answer may have been lost with it (the
        fleet takes a holder's ask as a renewal, a waiter's as keeping its place)."""
        for zone_id, lease in self._leases.items():
            self._send(lease.request_id, zone_id, m.ZoneRequestType.ACCESS,
                       self.config.lease_duration, lease.flow)

    def resume_goal(self, runtime: RobotRuntime) -> None:
        """Resume the goal this rule paused, if any (the order changes, or the zone is ours)."""
        if self._congested is not None:
            self._end_wait(runtime, granted=self._granted(self._congested))
        self._resume(runtime)

    def _resume(self, runtime: RobotRuntime) -> None:
        if self._paused_for is None:
            return
        self._paused_for = None
        self._moving_up_for = None
        self.wait_time += runtime.now() - self._wait_started
        try:
            runtime.resume()
        except PolynavError:
            log.debug("%s: nothing to resume", self.holder)

    def tick(self, now: float, runtime: RobotRuntime) -> None:
        """Ask, renew, release and wait as the rule says (every ``check_period``)."""
        self._now = now
        if now < self._next_check:
            return
        self._next_check = now + self.config.check_period
        plan = self._needed(runtime)
        needed = plan.needed
        self._entered &= set(needed)
        for run in (plan.inside, plan.ahead):
            if run is not None:
                self._ask(run, plan)
        for zone_id, lease in list(self._leases.items()):
            if zone_id not in needed:
                near = self._keeps_near(zone_id, lease, plan)
                if not (plan.active and lease.granted and lease.passage in plan.passages
                        and (near or now - lease.needed < self.config.release_grace)):
                    self._send(lease.request_id, zone_id, m.ZoneRequestType.RELEASE, 0.0)
                    del self._leases[zone_id]
                    continue
                # Kept: a segment of a passage it still needs within keep_behind (renewed while
                # it is), or which the path may come back to (release_grace). Another
                # passage's goes at once, or it would hold one while it waits for the next
                # (docs/fleet.md: why no deadlock).
                if not near:
                    continue
            else:
                lease.needed = now
            if lease.granted and lease.expiry - now < self.config.renew_before and (
                    now - lease.renew_sent > self.config.check_period * 5):
                lease.renew_sent = now
                self._send(lease.request_id, zone_id, m.ZoneRequestType.ACCESS,
                           self.config.lease_duration)
            elif not lease.granted and now - lease.heard > self.config.reask_after:
                lease.heard = now
                self._send(lease.request_id, zone_id, m.ZoneRequestType.ACCESS,
                           self.config.lease_duration, lease.flow)
        for run in (plan.inside, plan.ahead):
            if run is not None and self._missing(run) is None:
                self._entered |= set(run.zones)  # all of it ours: it drives through
        target, distance = self._target(plan)
        self._tell(runtime, needed, target)
        if self._paused_for is not None:
            if target is None:
                log.info("%s: %s granted, going on", self.holder, self._paused_for)
                self.resume_goal(runtime)
            elif distance > 0.0 and distance > self._stop_distance(target, plan.in_zone) + (
                    self.config.queue_spacing / 2):
                log.info("%s: moving up in line for %s", self.holder, target)
                self._resume(runtime)
                self._moving_up_for = target
            else:
                self._paused_for = target  # the wait goes on, for the next segment maybe
            return
        if self._moving_up_for is not None and (self._moving_up_for not in needed
                                                or self._granted(self._moving_up_for)):
            self._moving_up_for = None
        blocking = None
        if target is not None:
            if distance == 0.0 and plan.routed and self._leases.get(target, _NONE).queued:
                blocking = target, 0.0  # it starts in a passage another robot holds: it waits
            elif 0.0 < distance <= self._stop_distance(target, plan.in_zone):
                blocking = target, distance
        stack = runtime.navigation_stack
        if (blocking is not None and stack is not None
                and stack.navigator.state is NavigationState.RUNNING):
            runtime.pause(make_way=True)
            self._paused_for = blocking[0]
            if self._congested is None:
                self._congested = blocking[0]
                runtime.publish(events.TrafficWaitStarted(*_when(runtime), blocking[0]))
            self._wait_started = now
            if blocking[0] != self._moving_up_for:
                self.waits += 1
            self._moving_up_for = None
            log.info("%s: waiting for %s (%.2f m ahead)", self.holder, blocking[0], blocking[1])

    def _ask(self, run: _Run, plan: _Plan) -> None:
        """Ask for the zones of ``run``: all that are missing when the robot drives through it
        already; otherwise one at a time, in ascending zone order, the next only once those
        before it are granted, and none held or asked beyond the first missing one (the
        global order that keeps waiters from waiting on each other, docs/fleet.md)."""
        if self._driving(run):
            for zone_id in run.zones:
                if zone_id not in self._leases:
                    self._request(zone_id, plan.needed[zone_id], run)
            return
        missing = self._missing(run)
        if missing is None:
            return
        after = False
        for zone_id in run.ordered:
            if zone_id == missing:
                after = True
                if zone_id not in self._leases:
                    self._request(zone_id, plan.needed[zone_id], run)
            elif after and zone_id in self._leases:
                # Asked or held out of order (the path changed): give it back for now.
                lease = self._leases.pop(zone_id)
                self._send(lease.request_id, zone_id, m.ZoneRequestType.RELEASE, 0.0)

    def _keeps_near(self, zone_id: str, lease: _ZoneLease, plan: _Plan) -> bool:
        """Whether held segment ``zone_id`` is within ``keep_behind`` and may be kept: the
        robot waits for no segment of that passage numbered below it (so a waiter still holds
        only segments below the one it waits for)."""
        if zone_id not in plan.near:
            return False
        run = next((r for r in (plan.inside, plan.ahead)
                    if r is not None and r.group == lease.passage), None)
        if run is None:
            return False
        missing = self._missing(run)
        return missing is None or lease.number < run.number(missing)

    def _driving(self, run: _Run) -> bool:
        """Whether the robot drives through ``run`` on leases it got for all of it."""
        return run.entry == 0.0 and run.zones[0] in self._entered and self._granted(
            run.zones[0])

    def _missing(self, run: _Run) -> str | None:
        """The lowest-numbered zone of ``run`` not granted, None when all are."""
        return next((z for z in run.ordered if not self._granted(z)), None)

    def _target(self, plan: _Plan) -> tuple[str | None, float]:
        """The zone the robot would wait for, and how far ahead its passage starts [m] (0: it
        stands in it): the first missing zone of the passage it stands in (unless it drives
        through it on its leases), else of the next passage ahead."""
        for run in (plan.inside, plan.ahead):
            if run is None or self._driving(run):
                continue
            missing = self._missing(run)
            if missing is not None:
                # Standing in it: it waits where it stands once told it is queued, and goes on
                # while the answers are on their way (each segment is asked for in turn).
                return missing, run.entry
        return None, math.inf

    def _tell(self, runtime: RobotRuntime, needed: dict[str, str | None],
              target: str | None) -> None:
        """Tell a passage newly found held by another (queued), and the end of a wait whose
        zone the robot got or no longer needs (one it moved up in line for included)."""
        for zone_id, lease in self._leases.items():
            if lease.queued and zone_id in needed and zone_id not in self._told_busy:
                self._told_busy.add(zone_id)
                runtime.publish(events.TrafficBusy(*_when(runtime), zone_id))
        self._told_busy &= {z for z in needed if not self._granted(z)}
        zone = self._congested
        if zone is not None and self._paused_for is None and target is None:
            self._end_wait(runtime, granted=self._granted(zone))

    def _end_wait(self, runtime: RobotRuntime, *, granted: bool) -> None:
        zone = self._congested
        assert zone is not None
        self._congested = None
        runtime.publish(events.TrafficWaitEnded(*_when(runtime), zone, granted))

    def _stop_distance(self, zone_id: str, in_zone: bool) -> float:
        """How far before ``zone_id`` the robot stops if it is not granted: further back the
        further it is from the front of the line, but never in another zone (a robot waiting
        there would hold one zone while it waits for the next, or stand in a mouth)."""
        lease = self._leases.get(zone_id)
        place = lease.place if lease is not None and lease.queued and not in_zone else 0
        config = self.config
        return min(config.stop_distance + config.queue_spacing * place, config.lookahead)

    def _granted(self, zone_id: str) -> bool:
        lease = self._leases.get(zone_id)
        return lease is not None and lease.granted

    def _needed(self, runtime: RobotRuntime) -> _Plan:
        """The passages the robot needs now: the one it stands in and the next one ahead,
        with the way it goes through each zone of them it has not asked for yet."""
        stack = runtime.navigation_stack
        name = runtime.map_name
        zmap = self._zones.get(name) if name is not None else None
        if stack is None or zmap is None:
            return _Plan()
        navigator = stack.navigator
        if navigator.state not in (NavigationState.RUNNING, NavigationState.PAUSED):
            return _Plan()
        pose = runtime.status().pose
        path: Path | None = navigator.path
        current = zmap.zone_at(pose.x, pose.y)
        skip = 0
        if (current and path is not None and not self._granted(zmap.zone_id(current))
                and zmap.leaves(path, pose.x, pose.y, current, within=self.config.leave_within)):
            skip = zmap.group(current)  # on its way out
        inside: _Run | None = None
        ahead: _Run | None = None
        config = self.config
        runs = [] if path is None else zmap.runs(
            path, pose.x, pose.y, reach=config.lookahead + config.keep_margin, skip_group=skip)
        for run in runs:
            found = _Run.of(zmap, run)
            if current and not skip and inside is None and ahead is None and run.entry == 0.0:
                inside = found
                continue
            if run.entry <= config.lookahead or any(z in self._leases for z in found.zones):
                ahead = found
            break
        if current and not skip and inside is None:
            # It stands in a zone its path does not start in (a sample off), or has no path:
            # that zone alone.
            inside = _Run.of(zmap, ZoneRun(zmap.group(current), 0.0, (current,), (0.0,)))
        if inside is not None and self._missing(inside) is None:
            self._entered |= set(inside.zones)
        if inside is not None and ahead is not None and not self._driving(inside):
            # Waiting in one passage, it holds nothing of the next (docs/fleet.md: why no
            # deadlock).
            ahead = None
        needed: dict[str, str | None] = {}
        for passage in (inside, ahead):
            if passage is None:
                continue
            for zone_id, number in zip(passage.zones, passage.numbers, strict=True):
                needed[zone_id] = None if zone_id in self._leases or path is None else (
                    zmap.flow(path, pose.x, pose.y, number))
        near: frozenset[str] = frozenset()
        if any(lease.granted and z not in needed for z, lease in self._leases.items()):
            near = frozenset(zmap.zone_id(n) for n in zmap.zones_near(
                pose.x, pose.y, config.keep_behind))
        return _Plan(needed, inside, ahead, current != 0, active=True, routed=path is not None,
                     near=near)

    def _request(self, zone_id: str, flow: str | None, run: _Run) -> None:
        request_id = f"{self.holder}-{next(self._requests)}"
        self._leases[zone_id] = _ZoneLease(request_id, flow=flow, heard=self._now,
                                           passage=run.group, number=run.number(zone_id))
        self._send(request_id, zone_id, m.ZoneRequestType.ACCESS, self.config.lease_duration,
                   flow)


def _when(runtime: RobotRuntime) -> tuple[float, int]:
    """The stamp and attempt id of an event the rule tells on the robot's bus."""
    attempt = runtime.status().attempt_id
    return runtime.now(), attempt if attempt is not None else 0
