"""The fleet manager's records: missions, orders, leases and the audit trail, in SQLite or
PostgreSQL (DESIGN §9), for one fleet manager or several sharing one PostgreSQL.

Nothing here is kept in process memory between calls: each method is one transaction on the
database (:mod:`polynav.fleet.records.database`), so two fleet-manager processes see one queue
of missions and one book of leases, and a manager that restarts finds both as they were.

The leases follow the rules of the in-memory :class:`~polynav.leases.book.LeaseBook`: a lease
is live while ``now < expires_at``, the holder extends it with :meth:`FleetRecords.renew`
(refused once it has lapsed), asking again while holding gives the same lease back, and a
resource of capacity N has at most N live holders. What the records add is that the database,
not memory, enforces the capacity: see :mod:`polynav.fleet.records.schema`. What they leave to
the caller is the waiting: a refused request is answered ``None`` and asked again (the lease
book's queue, flows and ``max_hold`` stay in the fleet manager).

Every change is written to the audit trail in the transaction that makes it, so the trail
never tells of a change that did not happen, nor misses one that did.
"""

from __future__ import annotations

import logging
import uuid
from collections.abc import Mapping, Sequence
from types import TracebackType
from typing import Any

from sqlalchemy import Connection, insert, select, update

from polynav.errors import Conflict, NotFound
from polynav.fleet.records import schema as s
from polynav.fleet.records.checks import (
    check_json,
    check_name,
    check_order,
    check_stops,
    check_time,
)
from polynav.fleet.records.database import Isolation, RecordsConfig, RecordsDatabase
from polynav.fleet.records.leases import LeaseRecords
from polynav.fleet.records.rows import mission_of, order_of
from polynav.fleet.records.values import AuditEntry, Mission, MissionState, Order, OrderState

log = logging.getLogger(__name__)

_SER = Isolation.SERIALIZABLE
_RC = Isolation.READ_COMMITTED


class FleetRecords(LeaseRecords):
    """The records of one site's fleet (see the module docstring). Open with :meth:`open`;
    every method takes the site time ``now`` [s] where it changes something. The leases'
    methods are :class:`~polynav.fleet.records.leases.LeaseRecords`'."""

    @classmethod
    def open(cls, url: str, *, name: str = "fleet",
             config: RecordsConfig | None = None) -> FleetRecords:
        """Open the records at ``url`` (``sqlite:///path`` or ``postgresql://user@host/db``),
        creating the tables that are missing.

        Args:
            url: the database; ``postgresql://`` is driven by psycopg 3.
            name: this fleet manager's name, the ``actor`` of its audit entries.
            config: how long to wait for the database.

        Raises:
            FleetRecordsError: an unsupported URL, or the database not reached within
                ``config.connect_wait`` (the message names the URL without its password).
            InvalidRequest: an empty name.
        """
        check_name("name", name)
        return cls(RecordsDatabase.open(url, config, application_name=f"polynav-{name}"), name)

    @property
    def is_postgres(self) -> bool:
        return self._db.is_postgres

    def close(self) -> None:
        self._db.close()

    def __enter__(self) -> FleetRecords:
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        self.close()

    # ------------------------------------------------------------------ missions

    def add_mission(self, stops: Sequence[Mapping[str, Any]], *, now: float,
                    mission_id: str | None = None) -> Mission:
        """Queue a mission through ``stops`` (each a JSON object naming at least its
        ``point``); returns it. Adding the same id with the same stops again returns the
        mission as it is (a retried request); with other stops it is a conflict.

        Raises:
            InvalidRequest: no stops, a stop without a point, stops not JSON, a bad id or time.
            Conflict: ``mission_id`` is taken by a mission with other stops.
        """
        now = check_time(now)
        stop_list = check_stops(stops)
        mid = uuid.uuid4().hex if mission_id is None else mission_id
        check_name("mission_id", mid)

        def work(conn: Connection) -> Mission:
            row = conn.execute(select(s.missions).where(s.missions.c.id == mid)).first()
            if row is not None:
                if list(row.stops) != stop_list:
                    raise Conflict(f"mission {mid!r} exists with other stops")
                return mission_of(row)
            conn.execute(insert(s.missions).values(
                id=mid, state=MissionState.QUEUED.value, stops=stop_list, robot=None,
                created=now, updated=now, attempts=0))
            self._audit(conn, now, "mission.added", mission=mid, stops=stop_list)
            return self._mission_in(conn, mid)

        return self._db.run(work, _RC)

    def claim_mission(self, robot: str, *, now: float,
                      mission_id: str | None = None) -> Mission | None:
        """Give ``robot`` the oldest queued mission (a requeued one keeps its place by when it
        was added), or None when none is queued; with ``mission_id``, that mission if it is
        still queued (the one the robot was chosen for), else None. A robot does one mission
        at a time: while it has an active one, that one is returned (so a retried claim takes
        no second mission).

        On PostgreSQL the oldest queued row is taken ``FOR UPDATE SKIP LOCKED``: two managers
        claiming at once for two robots get two missions, neither waits for the other.

        Raises:
            InvalidRequest: an empty robot name or a bad time.
        """
        check_name("robot", robot)
        now = check_time(now)
        return self._db.run(lambda conn: self._claim_in(conn, robot, now, mission_id), _RC)

    def _claim_in(self, conn: Connection, robot: str, now: float,
                  mission_id: str | None) -> Mission | None:
        m = s.missions.c
        active = conn.execute(select(s.missions).where(
            m.robot == robot, m.state == MissionState.ACTIVE.value)).first()
        if active is not None:
            return mission_of(active)
        queued = select(m.id, m.attempts).where(m.state == MissionState.QUEUED.value)
        if mission_id is not None:
            queued = queued.where(m.id == mission_id)
        oldest = conn.execute(queued.order_by(m.created, m.seq).limit(1)
                              .with_for_update(skip_locked=True)).first()
        if oldest is None:
            return None
        conn.execute(update(s.missions).where(m.id == oldest.id).values(
            state=MissionState.ACTIVE.value, robot=robot, updated=now,
            attempts=oldest.attempts + 1))
        self._audit(conn, now, "mission.claimed", mission=oldest.id, robot=robot,
                    attempt=oldest.attempts + 1)
        return self._mission_in(conn, oldest.id)

    def claim_missions(self, claims: Sequence[tuple[str, str]], *,
                       now: float) -> tuple[tuple[str, Mission], ...]:
        """:meth:`claim_mission` of each (robot, mission id) in ``claims``, in one transaction;
        the (robot, mission) pairs claimed (a mission no longer queued is left out, and so is
        a robot that has an active mission already)."""
        for robot, mission_id in claims:
            check_name("robot", robot)
            check_name("mission_id", mission_id)
        now = check_time(now)

        def work(conn: Connection) -> tuple[tuple[str, Mission], ...]:
            out = []
            for robot, mission_id in claims:
                got = self._claim_in(conn, robot, now, mission_id)
                if got is not None and got.mission_id == mission_id:
                    out.append((robot, got))
            return tuple(out)

        return self._db.run(work, _RC)

    def resume_mission(self, mission_id: str, robot: str, *, now: float) -> Mission | None:
        """Give a queued mission back to ``robot``, which was doing it when it was lost and is
        back still doing it (its state names the mission's order): active again, on the same
        attempt (no new claim); None when the mission is no longer queued (another robot
        claimed it, or it was cancelled) or ``robot`` has another active mission.

        Raises:
            NotFound: no such mission. InvalidRequest: an empty robot name or a bad time.
        """
        check_name("robot", robot)
        now = check_time(now)
        m = s.missions.c

        def work(conn: Connection) -> Mission | None:
            self._mission_in(conn, mission_id)  # NotFound
            if conn.execute(select(m.id).where(
                    m.robot == robot, m.state == MissionState.ACTIVE.value)).first():
                return None
            # One statement decides: of two managers resuming and claiming it at once, the
            # one whose update finds it still queued has it.
            taken = conn.execute(update(s.missions).where(
                m.id == mission_id, m.state == MissionState.QUEUED.value).values(
                state=MissionState.ACTIVE.value, robot=robot, updated=now))
            if taken.rowcount != 1:
                return None
            self._audit(conn, now, "mission.resumed", mission=mission_id, robot=robot)
            return self._mission_in(conn, mission_id)

        return self._db.run(work, _RC)

    def requeue_mission(self, mission_id: str, *, now: float) -> bool:
        """Put an active mission back in the queue (its robot gave up or was lost); returns
        whether it was active.

        Raises:
            NotFound: no such mission.
        """
        now = check_time(now)

        def work(conn: Connection) -> bool:
            mission = self._mission_in(conn, mission_id)
            if mission.state is not MissionState.ACTIVE:
                return False
            self._requeue(conn, mission, now)
            return True

        return self._db.run(work, _RC)

    def requeue_robot(self, robot: str, *, now: float) -> tuple[str, ...]:
        """Put ``robot``'s active mission back in the queue (its last will arrived); returns
        the ids requeued (none or one)."""
        check_name("robot", robot)
        now = check_time(now)
        m = s.missions.c

        def work(conn: Connection) -> tuple[str, ...]:
            rows = conn.execute(select(s.missions).where(
                m.robot == robot, m.state == MissionState.ACTIVE.value)).all()
            for row in rows:
                self._requeue(conn, mission_of(row), now)
            return tuple(row.id for row in rows)

        return self._db.run(work, _RC)

    def finish_mission(self, mission_id: str, *, now: float, failed: bool = False) -> Mission:
        """End an active mission as done (or failed); returns it. Finishing it the same way
        again returns it unchanged.

        Raises:
            NotFound: no such mission.
            Conflict: it is queued, or was finished the other way.
        """
        now = check_time(now)
        outcome = MissionState.FAILED if failed else MissionState.DONE

        def work(conn: Connection) -> Mission:
            mission = self._mission_in(conn, mission_id)
            if mission.state is outcome:
                return mission
            if mission.state is not MissionState.ACTIVE:
                raise Conflict(f"mission {mission_id!r} is {mission.state.value}, not active")
            self._finish_in(conn, mission, outcome, now)
            return self._mission_in(conn, mission_id)

        return self._db.run(work, _RC)

    def _finish_in(self, conn: Connection, mission: Mission, outcome: MissionState,
                   now: float) -> None:
        conn.execute(update(s.missions).where(s.missions.c.id == mission.mission_id).values(
            state=outcome.value, updated=now))
        self._audit(conn, now, f"mission.{outcome.value}", mission=mission.mission_id,
                    robot=mission.robot)

    def cancel_mission(self, mission_id: str, *, now: float) -> Mission:
        """Cancel a queued or active mission; returns it as it was before (an active one names
        the robot to tell). Cancelling it again returns it, cancelled, unchanged.

        Raises:
            NotFound: no such mission.
            Conflict: it has already ended (done or failed).
        """
        now = check_time(now)

        def work(conn: Connection) -> Mission:
            mission = self._mission_in(conn, mission_id)
            if mission.state is MissionState.CANCELLED:
                return mission
            if mission.state not in (MissionState.QUEUED, MissionState.ACTIVE):
                raise Conflict(f"mission {mission_id!r} has already ended "
                               f"({mission.state.value})")
            conn.execute(update(s.missions).where(s.missions.c.id == mission_id).values(
                state=MissionState.CANCELLED.value, updated=now))
            self._audit(conn, now, "mission.cancelled", mission=mission_id,
                        robot=mission.robot)
            return mission

        return self._db.run(work, _RC)

    def mission(self, mission_id: str) -> Mission:
        """The mission called ``mission_id``.

        Raises:
            NotFound: no such mission.
        """
        return self._db.run(lambda conn: self._mission_in(conn, mission_id), _RC)

    def missions(self, state: MissionState | None = None) -> tuple[Mission, ...]:
        """Every mission (or those in ``state``), oldest first."""
        query = select(s.missions).order_by(s.missions.c.created, s.missions.c.seq)
        if state is not None:
            query = query.where(s.missions.c.state == state.value)
        return self._db.run(lambda conn: tuple(map(mission_of, conn.execute(query))), _RC)

    # ------------------------------------------------------------------ orders

    def order_sent(self, order_id: str, update_id: int, *, robot: str, now: float,
                   mission: str | None = None) -> Order:
        """Record that order update (``order_id``, ``update_id``) was sent to ``robot``; sending
        it again moves its ``sent_at`` and counts the send. Earlier updates of the order not
        yet confirmed are superseded (re-sending them would be wrong)."""
        check_order(order_id, update_id, robot, mission)
        now = check_time(now)
        return self._db.run(
            lambda conn: self._sent_in(conn, order_id, update_id, robot, mission, now), _RC)

    def orders_sent(self, orders: Sequence[tuple[str, int, str, str | None]], *,
                    now: float) -> None:
        """:meth:`order_sent` of each (order id, update id, robot, mission) in ``orders``, in
        one transaction."""
        for order_id, update_id, robot, mission in orders:
            check_order(order_id, update_id, robot, mission)
        now = check_time(now)
        if not orders:
            return

        def work(conn: Connection) -> None:
            for order_id, update_id, robot, mission in orders:
                self._sent_in(conn, order_id, update_id, robot, mission, now)

        self._db.run(work, _RC)

    def _sent_in(self, conn: Connection, order_id: str, update_id: int, robot: str,
                 mission: str | None, now: float) -> Order:
        o = s.orders.c
        key = (o.order_id == order_id) & (o.update_id == update_id)
        row = conn.execute(select(s.orders).where(key)).first()
        if row is None:
            conn.execute(insert(s.orders).values(
                order_id=order_id, update_id=update_id, robot=robot, mission=mission,
                state=OrderState.SENT.value, sent_at=now, confirmed_at=None, sends=1))
            conn.execute(update(s.orders).where(
                o.order_id == order_id, o.update_id < update_id,
                o.state == OrderState.SENT.value).values(state=OrderState.SUPERSEDED.value))
            what = "order.sent"
        else:
            conn.execute(update(s.orders).where(key).values(sent_at=now,
                                                            sends=row.sends + 1))
            what = "order.resent"
        self._audit(conn, now, what, order_id=order_id, update_id=update_id, robot=robot,
                    mission=mission)
        return order_of(conn.execute(select(s.orders).where(key)).one())

    def order_confirmed(self, order_id: str, update_id: int, *, now: float) -> int:
        """Record that a robot's state named order ``order_id`` at update ``update_id``: that
        update, and any earlier one still waiting, is confirmed. Returns how many were."""
        check_name("order_id", order_id)
        now = check_time(now)
        return self._db.run(lambda conn: self._confirm_in(conn, order_id, update_id, now), _RC)

    def _confirm_in(self, conn: Connection, order_id: str, update_id: int, now: float) -> int:
        o = s.orders.c
        waiting = conn.execute(select(o.update_id, o.robot).where(
            o.order_id == order_id, o.update_id <= update_id,
            o.state == OrderState.SENT.value)).all()
        for row in waiting:
            conn.execute(update(s.orders).where(
                o.order_id == order_id, o.update_id == row.update_id).values(
                state=OrderState.CONFIRMED.value, confirmed_at=now))
            self._audit(conn, now, "order.confirmed", order_id=order_id,
                        update_id=row.update_id, robot=row.robot)
        return len(waiting)

    def progress(self, *, confirmed: Sequence[tuple[str, int]], done: Sequence[str],
                 now: float) -> tuple[str, ...]:
        """One tick's news from the robots' states in one transaction (a fleet of 1,000 made
        one transaction each): the order updates ``confirmed`` (as :meth:`order_confirmed`)
        and the missions ``done`` (as :meth:`finish_mission`); returns the missions of
        ``done`` finished now or before (one cancelled meanwhile is left as it is).

        Raises:
            NotFound: a mission of ``done`` that does not exist.
        """
        for order_id, _ in confirmed:
            check_name("order_id", order_id)
        now = check_time(now)

        def work(conn: Connection) -> tuple[str, ...]:
            for order_id, update_id in confirmed:
                self._confirm_in(conn, order_id, update_id, now)
            ended = []
            for mission_id in done:
                mission = self._mission_in(conn, mission_id)
                if mission.state is MissionState.ACTIVE:
                    self._finish_in(conn, mission, MissionState.DONE, now)
                if mission.state in (MissionState.ACTIVE, MissionState.DONE):
                    ended.append(mission_id)
            return tuple(ended)

        return self._db.run(work, _RC)

    def unconfirmed_orders(self, older_than: float) -> tuple[Order, ...]:
        """The order updates sent before ``older_than`` [s] that no state has confirmed (nor a
        later update superseded): the ones to send again. Oldest first."""
        older_than = check_time(older_than)
        o = s.orders.c
        query = (select(s.orders)
                 .where(o.state == OrderState.SENT.value, o.sent_at < older_than)
                 .order_by(o.sent_at, o.order_id, o.update_id))
        return self._db.run(lambda conn: tuple(map(order_of, conn.execute(query))), _RC)

    def order(self, order_id: str, update_id: int) -> Order:
        """One order update as recorded.

        Raises:
            NotFound: never sent.
        """
        o = s.orders.c

        def work(conn: Connection) -> Order:
            row = conn.execute(select(s.orders).where(
                o.order_id == order_id, o.update_id == update_id)).first()
            if row is None:
                raise NotFound("order", f"{order_id}/{update_id}")
            return order_of(row)

        return self._db.run(work, _RC)

    # ------------------------------------------------------------------ audit

    def note(self, what: str, *, now: float, **detail: Any) -> None:
        """Add an entry of the fleet manager's own to the audit trail (``detail`` is JSON)."""
        check_name("what", what)
        now = check_time(now)
        check_json("detail", detail)
        self._db.run(lambda conn: self._audit(conn, now, what, **detail), _RC)

    def audit(self, *, after: int = 0, limit: int | None = None) -> tuple[AuditEntry, ...]:
        """The audit entries with ids above ``after``, by id (at most ``limit``)."""
        a = s.audit.c
        query = select(s.audit).where(a.id > after).order_by(a.id)
        if limit is not None:
            query = query.limit(limit)
        return self._db.run(lambda conn: tuple(
            AuditEntry(entry_id=row.id, at=row.at, actor=row.actor, what=row.what,
                       detail=row.detail) for row in conn.execute(query)), _RC)

    # ------------------------------------------------------------------ internals

    def _mission_in(self, conn: Connection, mission_id: str) -> Mission:
        row = conn.execute(select(s.missions).where(s.missions.c.id == mission_id)).first()
        if row is None:
            raise NotFound("mission", mission_id)
        return mission_of(row)

    def _requeue(self, conn: Connection, mission: Mission, now: float) -> None:
        conn.execute(update(s.missions).where(s.missions.c.id == mission.mission_id).values(
            state=MissionState.QUEUED.value, robot=None, updated=now))
        self._audit(conn, now, "mission.requeued", mission=mission.mission_id,
                    robot=mission.robot)
