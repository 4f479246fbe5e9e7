"""The fleet manager: missions queued in the records and carried out by the fleet's robots.

:class:`FleetManager` runs on one clock, like :class:`~polynav.fleet.master_control.
MasterControl`, which it holds (orders, instant actions and zone answers go through it) beside
the fleet's :class:`~polynav.fleet.records.FleetRecords`. Each :meth:`FleetManager.tick`:

- reads every robot's ``connection`` (one subscription, ``uagv/v2/<manufacturer>/+/
  connection``; the master control's states and zone requests are one wildcard subscription
  each too, so the subscriptions do not grow with the fleet): a robot saying ONLINE, or first
  heard by its state or a zone request, is added to the fleet (and asked for its state); one
  whose last will arrives (CONNECTIONBROKEN) or that says OFFLINE loses its leases (the lease
  book's and the records') and its mission goes back in the queue, for another robot; back
  ONLINE, its first state says whether it still drives that mission's order: if no other
  robot has claimed the mission meanwhile it resumes it (same attempt; a restarted broker
  delivers every robot's will while the robots drive on), else it is told to cancel it;
- follows each robot's mission from its states: the order is confirmed by the first state
  naming it; the mission is done when the robot's state names the order with no node left to
  drive and no ``orderFailed``, and failed when an error refers to the order (rejected or
  failed): then it is queued again, up to :attr:`FleetManagerConfig.max_attempts` claims,
  after which it fails;
- every :attr:`FleetManagerConfig.dispatch_period`, sends again the orders no state has
  confirmed within :attr:`FleetManagerConfig.resend_after` (same orderId and orderUpdateId: a
  robot that had it ignores it), and dispatches the queue, oldest mission first, each to the
  best robot (:mod:`polynav.fleet.manager.dispatch`).

The lease book defers every grant to the records (:mod:`polynav.fleet.manager.ledger`), so
managers sharing one PostgreSQL never grant one lift car twice.

Its calls are thread-safe (one lock): the API reads and submits from its own thread while the
loop ticks. What happens to missions and robots is kept as :class:`FleetEvent` values for the
API's WebSocket (the latest :attr:`FleetManagerConfig.events_kept`).
"""

from __future__ import annotations

import datetime as dt
import itertools
import logging
import threading
from collections import deque
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from polynav.errors import InvalidRequest, NotFound, PolynavError
from polynav.fleet import messages as m
from polynav.fleet.interface import Transport
from polynav.fleet.manager.dispatch import (
    Candidate,
    Target,
    available,
    choose,
)
from polynav.fleet.manager.ledger import RecordsLedger
from polynav.fleet.manager.values import FleetEvent, FleetManagerConfig, RobotView, SitePoints
from polynav.fleet.master_control import MasterControl, Stop
from polynav.fleet.records import AuditEntry, FleetRecords, Mission, MissionState
from polynav.leases.book import Lease, LeaseBook, LeaseBookConfig

log = logging.getLogger(__name__)

@dataclass(slots=True)
class _Assignment:
    mission_id: str
    order_id: str
    confirmed: bool = False


class FleetManager:
    """Missions dispatched to the fleet's robots (see the module docstring).

    Args:
        transport: where the robots are.
        records: the fleet's records (missions, orders, leases, audit).
        site: the site's points, to turn a mission's stops into poses.
        levels: each map's floor level, for robots on another floor than a mission.
        leases: the lease book's timings.
        config: the manager's timings and limits.
        version: the VDA 5050 version spoken.
        manufacturer: the robots' manufacturer (their topics' third level).
        epoch: the UTC moment site time 0 stands for.
    """

    def __init__(self, transport: Transport, records: FleetRecords, site: SitePoints, *,
                 levels: Mapping[str, int] | None = None,
                 leases: LeaseBookConfig | None = None,
                 config: FleetManagerConfig | None = None,
                 version: str = m.DEFAULT_VERSION,
                 manufacturer: str = m.DEFAULT_MANUFACTURER,
                 epoch: dt.datetime | None = None) -> None:
        self.records = records
        self.site = site
        self.levels = dict(levels or {})
        self.config = config or FleetManagerConfig()
        self.ledger = RecordsLedger(records)
        self.leases = LeaseBook(leases, ledger=self.ledger)
        self.master = MasterControl(transport, self.leases, version=version,
                                    manufacturer=manufacturer, epoch=epoch)
        self.manufacturer = manufacturer
        self._connections = transport.subscribe(
            f"{m.INTERFACE}/{m.MAJOR}/{manufacturer}/+/{m.TOPICS[m.Connection]}")
        self._lock = threading.RLock()
        self._now = 0.0
        self._next_dispatch = float("-inf")
        self._next_queue_poll = float("-inf")
        self._queue_changed = True
        self._link: dict[str, str] = {}
        self._assignments: dict[str, _Assignment] = {}
        # Robots lost while doing a mission (requeued): the job they were doing, kept until
        # they come back and say in a state after their return whether they still do it.
        self._away: dict[str, _Assignment] = {}
        self._returned: dict[str, float] = {}  # robot -> when it said ONLINE again
        self._held: dict[str, float] = {}  # mission -> until when it waits for its lost robot
        self._events: deque[FleetEvent] = deque(maxlen=self.config.events_kept)
        self._seq = itertools.count(1)

    # -- robots --------------------------------------------------------------------------------

    def add_robot(self, serial: str) -> None:
        """Take ``serial`` into the fleet, ONLINE (a robot of this process, which has no
        ``connection`` topic of its own); a known robot is left as it is.

        Raises:
            InvalidRequest: an empty serial number or one with ``/``, ``+`` or ``#``.
        """
        _check_serial(serial)
        with self._lock:
            if serial not in self._link:
                if not self.master.knows(serial):
                    self.master.add_robot(serial)
                self._link[serial] = m.ConnectionState.ONLINE.value

    def robots(self) -> list[RobotView]:
        """Every robot the manager has heard of, by serial number."""
        with self._lock:
            return [self._view(serial) for serial in sorted(self._link)]

    def robot(self, serial: str) -> RobotView:
        """One robot.

        Raises:
            NotFound: no robot ``serial`` in the fleet.
        """
        with self._lock:
            if serial not in self._link:
                raise NotFound("robot", serial)
            return self._view(serial)

    # -- missions ------------------------------------------------------------------------------

    def submit(self, stops: Sequence[Mapping[str, Any]], *,
               mission_id: str | None = None) -> Mission:
        """Queue a mission through ``stops`` (each ``{"point": name, "map": map}``, in order);
        it is dispatched at the next dispatch.

        Raises:
            InvalidRequest: no stops, a stop that is not a point and a map.
            NotFound: a stop naming a point or a map the site does not have.
            Conflict: ``mission_id`` is taken by a mission with other stops.
        """
        checked = [self._stop(k, stop) for k, stop in enumerate(_stop_list(stops))]
        with self._lock:
            mission = self.records.add_mission(
                [{"point": s.point, "map": s.map_name} for s in checked], now=self._now,
                mission_id=mission_id)
            self._emit("mission.queued", mission=mission.mission_id,
                       stops=[s.point for s in checked])
            return mission

    def cancel(self, mission_id: str) -> Mission:
        """Cancel a queued or active mission (its robot is told to cancel its order); returns
        it as it is now.

        Raises:
            NotFound: no such mission. Conflict: it has already ended.
        """
        with self._lock:
            before = self.records.cancel_mission(mission_id, now=self._now)
            robot = before.robot
            if before.state is MissionState.ACTIVE and robot is not None:
                assignment = self._assignments.get(robot)
                if assignment is not None and assignment.mission_id == mission_id:
                    del self._assignments[robot]
                    self.master.cancel_order(robot)
            if before.state is not MissionState.CANCELLED:
                self._emit("mission.cancelled", mission=mission_id, robot=robot)
            return self.records.mission(mission_id)

    def mission(self, mission_id: str) -> Mission:
        """One mission. Raises: NotFound."""
        return self.records.mission(mission_id)

    def missions(self, state: MissionState | None = None) -> tuple[Mission, ...]:
        """Every mission (or those in ``state``), oldest first."""
        return self.records.missions(state)

    def live_leases(self) -> tuple[Lease, ...]:
        """The leases live now in the records (every manager's), by resource."""
        with self._lock:
            now = self._now
        return self.records.live_leases(now)

    def audit(self, *, after: int = 0, limit: int | None = None) -> tuple[AuditEntry, ...]:
        """The records' audit trail after entry ``after``."""
        return self.records.audit(after=after, limit=limit)

    def events_after(self, seq: int) -> list[FleetEvent]:
        """The events kept with ``seq`` above ``seq``, oldest first."""
        with self._lock:
            return [e for e in self._events if e.seq > seq]

    def now(self) -> float:
        """The site time of the last tick [s]."""
        with self._lock:
            return self._now

    # -- the clock -----------------------------------------------------------------------------

    def tick(self, now: float) -> None:
        """Read connections and states, follow missions, answer zone requests, re-send and
        dispatch (module docstring). A records database that stays unreachable is logged and
        tried again next tick: the robots keep being answered from memory meanwhile."""
        with self._lock:
            self._now = now
            # States and zone requests first: what a lost robot sent before its will came is
            # read before the will revokes its leases (not granted again after).
            self.master.tick(now)
            adopted = self._adopt(now)
            if self._read_connections(now) or adopted:
                self.master.answer_lease_changes()
            try:
                self._follow_missions(now)
                if now >= self._next_dispatch:
                    self._next_dispatch = now + self.config.dispatch_period
                    if any(not job.confirmed for job in self._assignments.values()):
                        self._resend(now)
                    if self._queue_changed or now >= self._next_queue_poll:
                        # The records are read when this manager changed the queue or freed
                        # a robot, else every queue_poll_period (other managers' missions,
                        # robots freed by orders not ours): a building at 40x real time
                        # would otherwise query them ~100 times a second for nothing.
                        self._queue_changed = False
                        self._next_queue_poll = now + self.config.queue_poll_period
                        self._dispatch(now)
            except PolynavError as exc:
                log.error("fleet manager: %s; trying again", exc)

    # -- connections ---------------------------------------------------------------------------

    def _read_connections(self, now: float) -> bool:
        """Take in the robots' connection messages; whether any robot's changed."""
        changed = False
        for message in self._connections.drain():
            if not isinstance(message, m.Connection):
                log.warning("a connection message not used: %s", message)
                continue
            serial = message.header.serial_number
            try:
                _check_serial(serial)
            except InvalidRequest as exc:
                log.warning("a connection message not used: %s", exc)
                continue
            state = message.connection_state.value
            before = self._link.get(serial)
            if before == state:
                continue
            changed = True
            try:
                self._connection_changed(serial, state, before, now)
            except PolynavError as exc:
                log.error("fleet manager: connection of %s to %s: %s", serial, state, exc)
        return changed

    def _adopt(self, now: float) -> bool:
        """Take into the fleet the robots the master control first heard by a state or a zone
        request (before their ``connection``, or with none of their own): a robot that speaks
        is ONLINE, as if it had said so; whether any was."""
        adopted = False
        for serial in self.master.take_adopted():
            if serial in self._link:
                continue
            adopted = True
            try:
                self._connection_changed(serial, m.ConnectionState.ONLINE.value, None, now)
            except PolynavError as exc:
                log.error("fleet manager: adopting %s: %s", serial, exc)
        return adopted

    def _connection_changed(self, serial: str, state: str, before: str | None,
                            now: float) -> None:
        if not self.master.knows(serial):
            self.master.add_robot(serial)
        self._link[serial] = state
        self.master.set_online(serial, state == m.ConnectionState.ONLINE.value)
        log.info("robot %s is %s (was %s)", serial, state, before or "unknown")
        self.records.note("robot.connection", now=now, robot=serial, state=state)
        self._emit("robot.connection", robot=serial, state=state)
        if state == m.ConnectionState.ONLINE.value:
            if serial in self._away:
                # Whether it resumes its mission or is told to cancel it waits for a state
                # sent after its return (_follow_returned); no new mission meanwhile.
                self._returned[serial] = now
            self.master.request_state(serial)
            return
        released = self.leases.release_all(serial, now=now)
        # Besides those this manager's book held (released above, in the records too): any
        # another manager granted it.
        revoked = [lease.resource for lease in self.records.revoke_all(serial, now=now)]
        requeued = self.records.requeue_robot(serial, now=now)
        job = self._assignments.pop(serial, None)
        self._returned.pop(serial, None)
        if job is not None and job.mission_id in requeued:
            self._away[serial] = job
            self._held[job.mission_id] = now + self.config.lost_grace
        log.warning("robot %s lost (%s): leases %s revoked, missions %s requeued", serial,
                    state, sorted({*released, *revoked}), list(requeued))
        for mission_id in requeued:
            self._emit("mission.requeued", mission=mission_id, robot=serial,
                       why=state.lower())

    # -- missions ------------------------------------------------------------------------------

    def _follow_returned(self, now: float) -> None:
        """Robots back after their last will: one whose state since its return names the
        order of its requeued mission takes that mission back, if no other robot has claimed
        it (a broker restart delivers every robot's will, and the robots drive on: their
        missions should not start again from the queue); one whose mission has gone to
        another robot is told to cancel the order, so it is not done twice."""
        for serial, since in list(self._returned.items()):
            at = self.master.state_time(serial)
            state = self.master.state(serial)
            if state is None or at is None or at < since:
                continue  # no state since it came back yet
            del self._returned[serial]
            job = self._away.pop(serial)
            self._held.pop(job.mission_id, None)
            self._queue_changed = True
            if state.order_id != job.order_id:
                continue  # not doing it (restarted?): the mission waits in the queue
            resumed = self.records.resume_mission(job.mission_id, serial, now=now)
            if resumed is None:
                if _running(state):
                    self.master.cancel_order(serial)
                continue
            job.confirmed = True
            self._assignments[serial] = job
            log.info("mission %s resumed by %s, back on the broker", job.mission_id, serial)
            self._emit("mission.resumed", mission=job.mission_id, robot=serial,
                       order=job.order_id)

    def _follow_missions(self, now: float) -> None:
        self._follow_returned(now)
        started: list[tuple[str, _Assignment]] = []
        done: list[tuple[str, _Assignment]] = []
        failed: list[tuple[str, _Assignment, str]] = []
        for serial, job in self._assignments.items():
            state = self.master.state(serial)
            if state is None:
                continue
            ours = state.order_id == job.order_id
            if ours and not job.confirmed:
                started.append((serial, job))
            errors = [e for e in state.errors if any(
                r.reference_key == "orderId" and r.reference_value == job.order_id
                for r in e.error_references)]
            if errors and (not ours or any(e.error_type == "orderFailed" for e in errors)):
                failed.append((serial, job,
                               f"{errors[-1].error_type}: {errors[-1].error_description}"))
            elif ours and not state.node_states:
                done.append((serial, job))
        if started or done:
            # One transaction for the tick's confirmations and ends; memory follows once it
            # is written (a failed write leaves both for the next tick).
            ended = set(self.records.progress(
                confirmed=[(job.order_id, 0) for _, job in started],
                done=[job.mission_id for _, job in done], now=now))
            for serial, job in started:
                job.confirmed = True
                self._emit("mission.started", mission=job.mission_id, robot=serial,
                           order=job.order_id)
            for serial, job in done:
                del self._assignments[serial]
                if job.mission_id in ended:
                    log.info("mission %s done by %s", job.mission_id, serial)
                    self._emit("mission.done", mission=job.mission_id, robot=serial)
        for serial, job, why in failed:
            self._attempt_failed(serial, job, why, now)

    def _attempt_failed(self, serial: str, job: _Assignment, why: str, now: float) -> None:
        del self._assignments[serial]
        mission = self.records.mission(job.mission_id)
        if mission.state is not MissionState.ACTIVE:
            return
        if mission.attempts >= self.config.max_attempts:
            self.records.finish_mission(job.mission_id, now=now, failed=True)
            log.warning("mission %s failed on %s after %d attempts: %s", job.mission_id,
                        serial, mission.attempts, why)
            self._emit("mission.failed", mission=job.mission_id, robot=serial, why=why)
        else:
            self.records.requeue_mission(job.mission_id, now=now)
            log.warning("mission %s requeued (attempt %d on %s failed: %s)", job.mission_id,
                        mission.attempts, serial, why)
            self._emit("mission.requeued", mission=job.mission_id, robot=serial, why=why)

    def _resend(self, now: float) -> None:
        for order in self.records.unconfirmed_orders(now - self.config.resend_after):
            job = self._assignments.get(order.robot)
            if job is None or job.order_id != order.order_id or job.confirmed:
                continue  # another manager's, or no longer ours
            if order.sends >= self.config.max_sends:
                self._attempt_failed(order.robot, job,
                                     f"order not confirmed after {order.sends} sends", now)
            elif self.master.resend_order(order.robot, order.order_id):
                self.records.order_sent(order.order_id, order.update_id, robot=order.robot,
                                        now=now, mission=order.mission)

    def _dispatch(self, now: float) -> None:
        queued = self.records.missions(MissionState.QUEUED)
        if not queued:
            return
        # The robots weighed once per dispatch, not per mission, and only those free to go
        # (1,000 robots and a queue of 50 were 50,000 candidates weighed a dispatch); each
        # robot given a mission is taken out.
        candidates = {c.serial: c for c in self._candidates()
                      if available(c, self.config.dispatch)}
        chosen: list[tuple[str, str]] = []
        for mission in queued:
            until = self._held.get(mission.mission_id, now)
            if until > now:  # its lost robot may come back still doing it
                self._next_queue_poll = min(self._next_queue_poll, until)
                continue
            self._held.pop(mission.mission_id, None)
            try:
                first = self._stop(0, mission.stops[0])
            except (InvalidRequest, NotFound) as exc:
                # Its point left the site since it was queued: no robot can ever do it.
                log.warning("mission %s cancelled: %s", mission.mission_id, exc)
                self.records.cancel_mission(mission.mission_id, now=now)
                self._emit("mission.cancelled", mission=mission.mission_id, why=str(exc))
                continue
            serial = choose(list(candidates.values()), Target(first.map_name, first.pose.x,
                                                               first.pose.y),
                            levels=self.levels, config=self.config.dispatch)
            if serial is None:
                break
            del candidates[serial]
            chosen.append((serial, mission.mission_id))
            if len(chosen) >= self.config.max_dispatch:
                # The rest at the next tick, not a dispatch period later.
                self._queue_changed = True
                self._next_dispatch = now
                break
        if not chosen:
            return
        # One transaction for the claims and one for the orders sent: a fleet of 1,000 freed
        # dozens of robots a dispatch, and a transaction each held the states unread.
        claimed = self.records.claim_missions(chosen, now=now)  # another manager's: left out
        sent = [self._start(serial, mission, now) for serial, mission in claimed]
        self.records.orders_sent([(order_id, 0, serial, mission_id)
                                  for order_id, serial, mission_id in filter(None, sent)],
                                 now=now)

    def _start(self, serial: str, mission: Mission,
               now: float) -> tuple[str, str, str] | None:
        """Send ``mission``'s order to ``serial``; (order id, serial, mission id) to record as
        sent, None if it could not be sent (the mission is queued again)."""
        order_id = f"{mission.mission_id}-{mission.attempts}"
        try:
            stops = [self._stop(k, stop) for k, stop in enumerate(mission.stops)]
            self.master.send_order(serial, stops, order_id=order_id)
        except PolynavError as exc:
            log.warning("mission %s not sent to %s: %s", mission.mission_id, serial, exc)
            self.records.requeue_mission(mission.mission_id, now=now)
            return None
        self._assignments[serial] = _Assignment(mission.mission_id, order_id)
        log.info("mission %s dispatched to %s (attempt %d)", mission.mission_id, serial,
                 mission.attempts)
        self._emit("mission.dispatched", mission=mission.mission_id, robot=serial,
                   order=order_id, attempt=mission.attempts)
        return order_id, serial, mission.mission_id

    def _candidates(self) -> list[Candidate]:
        out = []
        for serial, link in self._link.items():
            state = self.master.state(serial)
            position = state.agv_position if state is not None else None
            out.append(Candidate(
                serial=serial,
                online=link == m.ConnectionState.ONLINE.value,
                busy=(serial in self._assignments or serial in self._returned
                      or state is None or _running(state)),
                in_error=state is not None and any(e.error_level == "FATAL"
                                                   for e in state.errors),
                battery=state.battery_state.battery_charge if state is not None else 0.0,
                map_name=position.map_id if position is not None else None,
                x=position.x if position is not None else 0.0,
                y=position.y if position is not None else 0.0,
            ))
        return out

    # -- helpers -------------------------------------------------------------------------------

    def _stop(self, k: int, stop: object) -> Stop:
        if not isinstance(stop, Mapping):
            raise InvalidRequest(f"stops[{k}]", f"must be an object, got {stop!r}")
        point, map_name = stop.get("point"), stop.get("map")
        if not isinstance(point, str) or not point:
            raise InvalidRequest(f"stops[{k}].point", f"must be a point's name, got {point!r}")
        if not isinstance(map_name, str) or not map_name:
            raise InvalidRequest(f"stops[{k}].map", f"must be a map's name, got {map_name!r}")
        return Stop(point, map_name, self.site.point(map_name, point).pose)

    def _view(self, serial: str) -> RobotView:
        job = self._assignments.get(serial)
        return RobotView(serial, self._link[serial], self.master.state(serial),
                         self.master.state_time(serial), job.mission_id if job else None,
                         job.order_id if job else None)

    def _emit(self, kind: str, **detail: Any) -> None:
        if kind in _QUEUE_CHANGES:
            self._queue_changed = True
        event = FleetEvent(next(self._seq), self._now, kind, detail)
        self._events.append(event)


_QUEUE_CHANGES = frozenset({"mission.queued", "mission.requeued", "mission.done",
                            "mission.failed", "mission.cancelled", "robot.connection"})
"""Events after which the queue is dispatched at once (a mission to give, a robot free)."""


def _running(state: m.State) -> bool:
    """Whether the robot drives an order: nodes left, and the order not failed (a failed
    order keeps its nodes in the state)."""
    return bool(state.node_states) and not any(e.error_type == "orderFailed"
                                               for e in state.errors)


def _stop_list(stops: object) -> list[object]:
    if isinstance(stops, (str, bytes)) or not isinstance(stops, Sequence) or not stops:
        raise InvalidRequest("stops", "a mission needs a list of at least one stop")
    return list(stops)


def _check_serial(serial: object) -> None:
    if not isinstance(serial, str) or not serial or any(c in serial for c in "/+#"):
        raise InvalidRequest("serial_number", f"{serial!r}: non-empty, without / + or #")
