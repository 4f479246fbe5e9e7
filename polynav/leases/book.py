"""The lease book: named shared resources granted to one holder at a time, each with an expiry.

A *resource* is anything robots must not use at once: a lift car's session, a door, a narrow
corridor, a charger. It is named by a string (``"lift:A"``, ``"corridor:east"``) and has a
*capacity*, 1 unless set otherwise. A *holder* (a robot's id) asks for it with
:meth:`LeaseBook.request` and gets a :class:`Lease` with an expiry on the sim clock, or a place
in the resource's queue.

Rules, after the zone reservations of VDA 5050 3.0 (a ``zoneRequest`` is granted with a
``leaseExpiry`` and lapses unless renewed):

- **Leases expire.** A lease is live while ``now < expires_at``. The holder extends it with
  :meth:`LeaseBook.renew`; one not renewed lapses, so a robot that stops answering never holds a
  lift for ever. A renewal after the expiry is refused
  (:class:`~polynav.leases.errors.LeaseNotHeld`): the holder has lost the resource and must ask
  again.
- **Waiters are served first come, first served.** When the resource is full, or others already
  wait, the holder joins the end of the queue. When capacity frees (release, expiry) the head of
  the queue is granted at once; a newcomer never overtakes a waiter.
- **One way at a time.** A request may name a *flow* (the way the holder goes through, e.g.
  ``"EE"``: east along a corridor, ``"NE"``: north out of a door, then east): holders whose
  ways never head opposite share a resource beyond its capacity (robots following one another
  through a corridor never meet head-on), while one going against any of them waits until they
  are all out. Flows of compass sectors (``E``, ``N``, ``W``, ``S``,
  :meth:`polynav.fleet.zones.ZoneMap.flow`) go together when neither holds the opposite of a
  sector of the other (``"NE"`` with ``"EE"``, not with ``"ES"``); other flows when equal.
  A newcomer joins the holders only when no one waits, so the other way gets its turn once
  they have drained; and when the head of the queue goes in, the waiters further back that go
  its way (and the way of everyone inside) go in with it. Those they pass go against that
  group and would wait for it to drain anyway: going in together, the group drains in about
  the time of its slowest crossing instead of one crossing after another (one at a time, floor
  2's corridor on the demo was held all the time by 10 robots and queued six, issue 36).
- **No one waits for ever.** Each waiter has a deadline (``max_wait``); past it the waiter leaves
  the queue with a ``WAIT_TIMED_OUT`` event, so it can re-route or back off. One that asks again
  within ``reask_grace`` of its time-out still wants the resource: it goes back in the queue by
  when it first asked, not at the end (at the end, a robot behind five others for a lift car
  was sent to the back again every 180 s and waited 500 s while later robots rode). So does
  one that left the queue itself (a release while waiting) and asks again within the grace:
  a robot in line for a corridor whose re-planned path, round the robots waiting with it,
  briefly put the corridor beyond its look-ahead gave its place up and asked again four
  seconds later at the back, behind four robots that came after it (issue 36: past the
  mission timeout on the demo's floor 2, walkers on). And a
  holder cannot keep a resource by renewing for ever while others wait: past ``max_hold`` its
  renewal is refused (:class:`~polynav.leases.errors.LeaseRefused`). With both, every waiter is
  either granted or told to give up within a bounded time.

The book is pure: no clock, no threads, no I/O. Every call takes ``now`` [s], first brings the
book up to that time (expiring leases, timing out waiters, granting to the next in line), then acts.
What happened is recorded as :class:`LeaseEvent` values that the fleet drains with
:meth:`LeaseBook.take_events` and turns into messages to the robots.

A book may be given a :class:`~polynav.leases.interface.LeaseLedger` that has the last word on
every grant (the fleet manager's database, shared by several managers): a grant the ledger
refuses is not made, the holder waits in the queue as if the resource were full, and the book
asks the ledger again at each tick until it agrees. Renewals and every lease given back
(released, expired) are told to the ledger too.
"""

from __future__ import annotations

import enum
import logging
from collections import deque
from dataclasses import dataclass, field, replace

from polynav.errors import ConfigError, InvalidRequest
from polynav.leases.errors import LeaseNotHeld, LeaseRefused
from polynav.leases.interface import LeaseLedger

log = logging.getLogger(__name__)

_KEY = "fleet.lease."


@dataclass(frozen=True, slots=True)
class LeaseBookConfig:
    """Timing of the lease book, in seconds of (sim) clock time.

    Attributes:
        default_duration: a lease asked for without a duration lasts this long [s].
        max_duration: no single grant or renewal reaches further ahead than this [s].
        max_wait: a waiter that has not been granted within this leaves the queue [s].
        max_hold: while others wait, a holder may not renew once it has held the resource this
            long since it was granted [s]; alone, it may renew for ever.
        reask_grace: a waiter timed out, or one that left the queue, that asks again within
            this [s] keeps its place by when it first asked.
    """

    default_duration: float = 30.0
    max_duration: float = 300.0
    max_wait: float = 180.0
    max_hold: float = 600.0
    reask_grace: float = 10.0

    def __post_init__(self) -> None:
        for name in ("default_duration", "max_duration", "max_wait", "max_hold", "reask_grace"):
            value = getattr(self, name)
            if not value > 0.0:
                raise ConfigError(_KEY + name, f"must be > 0, got {value}")
        if self.default_duration > self.max_duration:
            raise ConfigError(_KEY + "default_duration",
                              f"must be <= max_duration ({self.max_duration}), "
                              f"got {self.default_duration}")


@dataclass(frozen=True, slots=True)
class Lease:
    """One holder's right to one resource until ``expires_at``.

    Attributes:
        lease_id: unique in the book; kept across renewals.
        resource: the resource's name.
        holder: who holds it (a robot id).
        granted_at: when it was granted [s]; ``max_hold`` counts from here.
        expires_at: the lease is live while ``now < expires_at`` [s].
        flow: the way the holder goes through, shared with holders of the same flow; None
            for a lease of its own.
    """

    lease_id: int
    resource: str
    holder: str
    granted_at: float
    expires_at: float
    flow: str | None = None

    def live_at(self, now: float) -> bool:
        return now < self.expires_at


class LeaseEventKind(enum.Enum):
    """What happened to a lease or a place in a queue."""

    GRANTED = "granted"
    RENEWED = "renewed"
    RELEASED = "released"
    EXPIRED = "expired"
    QUEUED = "queued"
    WAIT_TIMED_OUT = "wait_timed_out"
    WAIT_CANCELLED = "wait_cancelled"


@dataclass(frozen=True, slots=True)
class LeaseEvent:
    """One change in the book, at time ``at`` [s]; ``lease`` is set for lease changes."""

    kind: LeaseEventKind
    resource: str
    holder: str
    at: float
    lease: Lease | None = None


@dataclass(frozen=True, slots=True)
class Waiter:
    """A holder in a resource's queue, waiting since ``since`` until at most ``deadline`` [s]."""

    holder: str
    since: float
    deadline: float
    duration: float
    flow: str | None = None


@dataclass(slots=True)
class _Resource:
    capacity: int = 1
    leases: dict[str, Lease] = field(default_factory=dict)
    queue: deque[Waiter] = field(default_factory=deque)


class LeaseBook:
    """Leases on named resources, with FIFO queues, expiries and wait deadlines (see module doc)."""

    def __init__(self, config: LeaseBookConfig | None = None, *,
                 ledger: LeaseLedger | None = None) -> None:
        self.config = config or LeaseBookConfig()
        self.ledger = ledger
        self._resources: dict[str, _Resource] = {}
        self._events: list[LeaseEvent] = []
        self._now = float("-inf")
        self._next_id = 1
        self._timed_out: dict[tuple[str, str], Waiter] = {}  # (resource, holder): as it left

    # ------------------------------------------------------------------ set-up and queries

    def set_capacity(self, resource: str, capacity: int) -> None:
        """Let ``capacity`` holders share ``resource`` at once (a wide corridor, a big car).

        Raises:
            InvalidRequest: an empty name, a capacity below 1, or below the leases live now.
        """
        _check_name("resource", resource)
        if capacity < 1:
            raise InvalidRequest("capacity", f"must be >= 1, got {capacity}")
        res = self._resources.setdefault(resource, _Resource())
        if capacity < len(res.leases):
            raise InvalidRequest("capacity", f"{resource!r} has {len(res.leases)} live leases, "
                                             f"more than {capacity}")
        res.capacity = capacity

    def capacity(self, resource: str) -> int:
        res = self._resources.get(resource)
        return 1 if res is None else res.capacity

    def leases(self, resource: str) -> tuple[Lease, ...]:
        """The leases live on ``resource`` as of the last call, in grant order."""
        res = self._resources.get(resource)
        return () if res is None else tuple(res.leases.values())

    def lease(self, resource: str, holder: str) -> Lease | None:
        """``holder``'s live lease on ``resource`` as of the last call, if any."""
        res = self._resources.get(resource)
        return None if res is None else res.leases.get(holder)

    def waiters(self, resource: str) -> tuple[Waiter, ...]:
        """The queue of ``resource``, first in line first."""
        res = self._resources.get(resource)
        return () if res is None else tuple(res.queue)

    def queues(self) -> dict[str, tuple[Waiter, ...]]:
        """The queue of every resource someone waits for, first in line first (the master tells
        each waiter its place every tick: most resources have no queue, and are skipped)."""
        return {name: tuple(res.queue) for name, res in self._resources.items() if res.queue}

    def position(self, resource: str, holder: str) -> int | None:
        """``holder``'s place in the queue of ``resource`` (0 is next), or None if not waiting."""
        for i, w in enumerate(self.waiters(resource)):
            if w.holder == holder:
                return i
        return None

    def held_by(self, holder: str) -> tuple[Lease, ...]:
        """Every live lease of ``holder``, by resource name."""
        return tuple(res.leases[holder] for _, res in sorted(self._resources.items())
                     if holder in res.leases)

    def resources(self) -> tuple[str, ...]:
        """Every resource the book has seen, sorted."""
        return tuple(sorted(self._resources))

    def next_deadline(self) -> float | None:
        """The earliest expiry or wait deadline still ahead, for a caller that sleeps until then."""
        times = [lease.expires_at for res in self._resources.values()
                 for lease in res.leases.values()]
        times += [w.deadline for res in self._resources.values() for w in res.queue]
        return min(times) if times else None

    def take_events(self) -> list[LeaseEvent]:
        """The events since the last call, oldest first; the book forgets them."""
        events, self._events = self._events, []
        return events

    # ------------------------------------------------------------------ commands

    def tick(self, now: float) -> None:
        """Bring the book up to ``now``: expire leases, time out waiters, grant to the next in line.

        Raises:
            InvalidRequest: ``now`` is earlier than a time the book has already seen.
        """
        if now < self._now:
            raise InvalidRequest("now", f"time runs backwards ({now} < {self._now})")
        self._now = now
        grace = self.config.reask_grace
        for key, w in list(self._timed_out.items()):
            if now - w.deadline > grace:
                del self._timed_out[key]
        for name, res in self._resources.items():
            for holder, lease in list(res.leases.items()):
                if not lease.live_at(now):
                    del res.leases[holder]
                    log.info("lease on %s for %s expired at t=%.3f", name, holder, now)
                    if self.ledger is not None:
                        self.ledger.dropped(name, holder, now=now)
                    self._emit(LeaseEventKind.EXPIRED, lease, at=lease.expires_at)
            self._serve_queue(name, res, now)

    def request(self, resource: str, holder: str, *, now: float,
                duration: float | None = None, max_wait: float | None = None,
                flow: str | None = None) -> Lease | None:
        """Ask for ``resource`` for ``duration`` [s]: the lease if granted now, else None (queued).

        Asking again is safe: a holder gets its live lease back unchanged (use :meth:`renew` to
        extend it), and a waiter keeps its place in the queue. A waiter that was granted while it
        waited gets its lease from the next call.

        Args:
            resource: the resource's name.
            holder: who asks (a robot id).
            now: the current time [s].
            duration: how long the lease lasts once granted [s]; the book's default if None.
            max_wait: how long to wait at most [s]; the book's ``max_wait`` if None (and never
                longer than it).
            flow: the way the holder goes through: shared with holders of the same flow
                beyond the capacity (module docstring); None: a lease of its own.

        Raises:
            InvalidRequest: an empty name or flow, a duration out of (0, max_duration], a
                max_wait <= 0, or time running backwards.
        """
        _check_name("resource", resource)
        _check_name("holder", holder)
        if flow is not None:
            _check_name("flow", flow)
        length = self._duration(duration)
        if max_wait is not None and not max_wait > 0.0:
            raise InvalidRequest("max_wait", f"must be > 0, got {max_wait}")
        wait = self.config.max_wait if max_wait is None else min(max_wait, self.config.max_wait)
        self.tick(now)
        res = self._resources.setdefault(resource, _Resource())
        held = res.leases.get(holder)
        if held is not None:
            return held
        if any(w.holder == holder for w in res.queue):
            return None
        if not res.queue and _admits(res, flow) and self._ledger_takes(
                resource, res, holder, now, length, flow):
            return self._grant(resource, res, holder, now, length, flow)
        before = self._timed_out.pop((resource, holder), None)
        waiter = Waiter(holder=holder, since=now if before is None else before.since,
                        deadline=now + wait, duration=length, flow=flow)
        place = next((i for i, w in enumerate(res.queue) if w.since > waiter.since),
                     len(res.queue))
        res.queue.insert(place, waiter)
        if place == 0:
            self._serve_queue(resource, res, now)  # back at the head: it may go at once
            if holder in res.leases:
                return res.leases[holder]
        log.info("%s queued for %s at t=%.3f (place %d)", holder, resource, now, place)
        self._events.append(LeaseEvent(LeaseEventKind.QUEUED, resource, holder, now))
        return None

    def renew(self, resource: str, holder: str, *, now: float,
              duration: float | None = None) -> Lease:
        """Extend ``holder``'s live lease to ``now + duration``; the renewed lease is returned.

        Raises:
            LeaseNotHeld: the holder has no live lease (never granted, released or expired).
            LeaseRefused: others wait and the holder has held it for ``max_hold`` already.
            InvalidRequest: an empty name, a bad duration or time running backwards.
        """
        _check_name("resource", resource)
        _check_name("holder", holder)
        length = self._duration(duration)
        self.tick(now)
        res = self._resources.get(resource)
        held = None if res is None else res.leases.get(holder)
        if res is None or held is None:
            raise LeaseNotHeld(resource, holder, "no live lease (never granted, released or "
                                                 "expired)")
        if res.queue and now - held.granted_at >= self.config.max_hold:
            raise LeaseRefused(resource, holder,
                               f"held for {now - held.granted_at:.1f} s while "
                               f"{len(res.queue)} wait (max_hold {self.config.max_hold} s)")
        if self.ledger is not None:
            try:
                self.ledger.renewed(resource, holder, now=now, duration=length)
            except LeaseNotHeld:
                # The ledger no longer has it (revoked by another manager, lapsed there): the
                # holder has lost the resource here too.
                del res.leases[holder]
                self._emit(LeaseEventKind.RELEASED, held, at=now)
                self._serve_queue(resource, res, now)
                raise
        renewed = replace(held, expires_at=max(held.expires_at, now + length))
        res.leases[holder] = renewed
        self._emit(LeaseEventKind.RENEWED, renewed, at=now)
        return renewed

    def release(self, resource: str, holder: str, *, now: float) -> bool:
        """Give back ``holder``'s lease on ``resource``, or leave its queue; the next in line is
        granted at once. Returns whether there was anything to give back (releasing twice is
        harmless: messages may arrive more than once).

        Raises:
            InvalidRequest: an empty name or time running backwards.
        """
        _check_name("resource", resource)
        _check_name("holder", holder)
        self.tick(now)
        res = self._resources.get(resource)
        if res is None:
            return False
        held = res.leases.pop(holder, None)
        if held is not None:
            log.info("%s released %s at t=%.3f", holder, resource, now)
            if self.ledger is not None:
                self.ledger.dropped(resource, holder, now=now)
            self._emit(LeaseEventKind.RELEASED, held, at=now)
            self._serve_queue(resource, res, now)
            return True
        for w in res.queue:
            if w.holder == holder:
                res.queue.remove(w)
                # Remembered as a time-out now: asking again within the grace keeps its place.
                self._timed_out[(resource, holder)] = replace(w, deadline=now)
                self._events.append(
                    LeaseEvent(LeaseEventKind.WAIT_CANCELLED, resource, holder, now))
                return True
        return False

    def release_all(self, holder: str, *, now: float) -> tuple[str, ...]:
        """Give back every lease and queue place of ``holder`` (a robot leaving the fleet);
        returns the resources it had."""
        _check_name("holder", holder)
        self.tick(now)
        names = [name for name, res in sorted(self._resources.items())
                 if holder in res.leases or any(w.holder == holder for w in res.queue)]
        for name in names:
            self.release(name, holder, now=now)
        return tuple(names)

    # ------------------------------------------------------------------ internals

    def _duration(self, duration: float | None) -> float:
        if duration is None:
            return self.config.default_duration
        if not 0.0 < duration <= self.config.max_duration:
            raise InvalidRequest("duration", f"must be in (0, {self.config.max_duration}] s, "
                                             f"got {duration}")
        return float(duration)

    def _serve_queue(self, name: str, res: _Resource, now: float) -> None:
        # Time-outs go first, so a waiter past its deadline is never granted a lease it has
        # already given up on (its robot is re-routing).
        for w in list(res.queue):
            if w.deadline <= now:
                res.queue.remove(w)
                self._timed_out[(name, w.holder)] = w
                log.info("%s gave up waiting for %s at t=%.3f", w.holder, name, now)
                self._events.append(
                    LeaseEvent(LeaseEventKind.WAIT_TIMED_OUT, name, w.holder, w.deadline))
        let_in = False
        while res.queue and _admits(res, res.queue[0].flow):
            w = res.queue[0]
            if not self._ledger_takes(name, res, w.holder, now, w.duration, w.flow):
                break  # the head stays first in line; the ledger is asked again next tick
            res.queue.popleft()
            self._grant(name, res, w.holder, now, w.duration, w.flow)
            let_in = True
        if not let_in:
            return
        # The head went in: those further back going its way (and the way of everyone inside)
        # go in with it (module docstring).
        for w in list(res.queue):
            if w.flow is not None and _admits(res, w.flow) and self._ledger_takes(
                    name, res, w.holder, now, w.duration, w.flow):
                res.queue.remove(w)
                self._grant(name, res, w.holder, now, w.duration, w.flow)

    def _ledger_takes(self, name: str, res: _Resource, holder: str, now: float,
                      duration: float, flow: str | None) -> bool:
        """Whether the ledger (if any) agrees to this grant, and has recorded it."""
        if self.ledger is None:
            return True
        return self.ledger.take(name, holder, now=now, duration=duration,
                                capacity=res.capacity, flow=flow)

    def _grant(self, name: str, res: _Resource, holder: str, now: float,
               duration: float, flow: str | None = None) -> Lease:
        lease = Lease(lease_id=self._next_id, resource=name, holder=holder,
                      granted_at=now, expires_at=now + duration, flow=flow)
        self._next_id += 1
        res.leases[holder] = lease
        log.info("%s granted %s at t=%.3f until t=%.3f", holder, name, now, lease.expires_at)
        self._emit(LeaseEventKind.GRANTED, lease, at=now)
        return lease

    def _emit(self, kind: LeaseEventKind, lease: Lease, *, at: float) -> None:
        self._events.append(LeaseEvent(kind, lease.resource, lease.holder, at, lease))


_OPPOSITE = {"E": "W", "W": "E", "N": "S", "S": "N"}


def same_way(a: str, b: str) -> bool:
    """Whether holders of flows ``a`` and ``b`` may be in a resource together (module
    docstring): compass flows when neither heads opposite to the other anywhere, others when
    equal."""
    if set(a) <= _OPPOSITE.keys() and set(b) <= _OPPOSITE.keys():
        # "NWS" (up a passage, along, down another) goes against itself: two such robots
        # may meet in a passage one of them goes up and the other down.
        return not any(_OPPOSITE[c] in b for c in set(a))
    return a == b


def _admits(res: _Resource, flow: str | None) -> bool:
    """Whether ``res`` can take one more holder of ``flow`` now (queue aside)."""
    if len(res.leases) < res.capacity:
        # Below capacity: anyone, unless holders of a flow are inside and this one goes
        # against one of them.
        return flow is None or all(lease.flow is None or same_way(lease.flow, flow)
                                   for lease in res.leases.values())
    return flow is not None and all(lease.flow is not None and same_way(lease.flow, flow)
                                    for lease in res.leases.values())


def _check_name(field_name: str, value: str) -> None:
    if not isinstance(value, str) or not value.strip():
        raise InvalidRequest(field_name, f"must be a non-empty name, got {value!r}")

