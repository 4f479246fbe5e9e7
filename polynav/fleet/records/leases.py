"""The lease part of the fleet records (see :mod:`polynav.fleet.records.store`): leases granted,
renewed, released, revoked and expired, each in one transaction with its audit entry; the
database, not memory, keeps a resource to its capacity."""

from __future__ import annotations

import logging
from typing import Any

from sqlalchemy import Connection, Row, delete, insert, select, update

from polynav.errors import InvalidRequest
from polynav.fleet.records import schema as s
from polynav.fleet.records.checks import check_duration, check_name, check_time
from polynav.fleet.records.database import Isolation, RecordsDatabase
from polynav.fleet.records.rows import lease_of
from polynav.leases.book import Lease
from polynav.leases.errors import LeaseNotHeld

log = logging.getLogger(__name__)

_SER = Isolation.SERIALIZABLE
_RC = Isolation.READ_COMMITTED


class LeaseRecords:
    """The records' connection, audit trail and leases; :class:`~polynav.fleet.records.store.
    FleetRecords` adds missions and orders."""

    def __init__(self, db: RecordsDatabase, name: str) -> None:
        self._db = db
        self.name = name

    def grant_lease(self, resource: str, holder: str, *, now: float, duration: float,
                    capacity: int = 1) -> Lease | None:
        """Grant ``holder`` a lease on ``resource`` until ``now + duration``, or None when the
        resource already has ``capacity`` live holders. A holder that asks while holding gets
        its lease back unchanged (extend it with :meth:`renew`). Leases of the resource that
        have lapsed are expired first.

        Never grants more than ``capacity`` live leases, even to fleet managers racing on one
        database: the transaction is serializable (PostgreSQL) or holds the write lock
        (SQLite), and each lease takes one of ``capacity`` slots the database keeps unique.

        Raises:
            InvalidRequest: an empty name, a duration not > 0, a capacity below 1, a bad time.
        """
        check_name("resource", resource)
        check_name("holder", holder)
        now = check_time(now)
        duration = check_duration(duration)
        if isinstance(capacity, bool) or not isinstance(capacity, int) or capacity < 1:
            raise InvalidRequest("capacity", f"must be an integer >= 1, got {capacity!r}")
        c = s.leases.c

        def work(conn: Connection) -> Lease | None:
            rows = conn.execute(select(s.leases).where(c.resource == resource)).all()
            live = []
            for row in rows:
                if row.expires_at <= now:
                    self._drop_lease(conn, row, now, "lease.expired")
                else:
                    live.append(row)
            for row in live:
                if row.holder == holder:
                    return lease_of(row)
            free = sorted(set(range(capacity)) - {row.slot for row in live})
            if len(live) >= capacity or not free:
                return None
            inserted = conn.execute(insert(s.leases).values(
                resource=resource, slot=free[0], capacity=capacity, holder=holder,
                granted_at=now, expires_at=now + duration)).inserted_primary_key
            assert inserted is not None
            lease_id = int(inserted[0])
            self._audit(conn, now, "lease.granted", lease_id=lease_id, resource=resource,
                        holder=holder, slot=free[0], granted_at=now, expires_at=now + duration)
            return Lease(lease_id=lease_id, resource=resource, holder=holder,
                         granted_at=now, expires_at=now + duration)

        return self._db.run(work, _SER)

    def renew(self, resource: str, holder: str, *, now: float, duration: float) -> Lease:
        """Extend ``holder``'s live lease on ``resource`` to ``now + duration`` (never
        shortened); returns the renewed lease.

        Raises:
            LeaseNotHeld: the holder has no live lease (never granted, released, revoked or
                lapsed): it has lost the resource and must ask again.
            InvalidRequest: an empty name, a duration not > 0 or a bad time.
        """
        check_name("resource", resource)
        check_name("holder", holder)
        now = check_time(now)
        duration = check_duration(duration)
        c = s.leases.c

        def work(conn: Connection) -> Lease:
            row = conn.execute(select(s.leases).where(
                c.resource == resource, c.holder == holder)).first()
            if row is None or row.expires_at <= now:
                raise LeaseNotHeld(resource, holder, "no live lease (never granted, released, "
                                                     "revoked or expired)")
            expires_at = max(row.expires_at, now + duration)
            conn.execute(update(s.leases).where(c.lease_id == row.lease_id).values(
                expires_at=expires_at))
            self._audit(conn, now, "lease.renewed", lease_id=row.lease_id, resource=resource,
                        holder=holder, expires_at=expires_at)
            return Lease(lease_id=row.lease_id, resource=resource, holder=holder,
                         granted_at=row.granted_at, expires_at=expires_at)

        return self._db.run(work, _SER)

    def release(self, resource: str, holder: str, *, now: float) -> bool:
        """Give back ``holder``'s live lease on ``resource``; returns whether it had one
        (releasing twice is harmless: messages may arrive more than once)."""
        check_name("resource", resource)
        check_name("holder", holder)
        now = check_time(now)
        c = s.leases.c

        def work(conn: Connection) -> bool:
            row = conn.execute(select(s.leases).where(
                c.resource == resource, c.holder == holder)).first()
            if row is None:
                return False
            live: bool = row.expires_at > now
            self._drop_lease(conn, row, now, "lease.released" if live else "lease.expired")
            return live

        return self._db.run(work, _SER)

    def revoke_all(self, holder: str, *, now: float) -> tuple[Lease, ...]:
        """Take every live lease of ``holder`` back (its last will arrived: it will not release
        them itself); returns them, by resource."""
        check_name("holder", holder)
        now = check_time(now)

        def work(conn: Connection) -> tuple[Lease, ...]:
            rows = conn.execute(select(s.leases).where(s.leases.c.holder == holder)
                                .order_by(s.leases.c.resource)).all()
            revoked = []
            for row in rows:
                live = row.expires_at > now
                self._drop_lease(conn, row, now, "lease.revoked" if live else "lease.expired")
                if live:
                    revoked.append(lease_of(row))
            return tuple(revoked)

        return self._db.run(work, _SER)

    def expire(self, now: float) -> tuple[Lease, ...]:
        """Remove every lease lapsed by ``now`` (``expires_at <= now``); returns them, by
        expiry."""
        now = check_time(now)
        c = s.leases.c

        def work(conn: Connection) -> tuple[Lease, ...]:
            rows = conn.execute(select(s.leases).where(c.expires_at <= now)
                                .order_by(c.expires_at, c.lease_id)).all()
            for row in rows:
                self._drop_lease(conn, row, now, "lease.expired")
            return tuple(map(lease_of, rows))

        return self._db.run(work, _SER)

    def live_leases(self, now: float, resource: str | None = None) -> tuple[Lease, ...]:
        """The leases live at ``now`` (on ``resource``, or on all), by resource and grant."""
        now = check_time(now)
        c = s.leases.c
        query = select(s.leases).where(c.expires_at > now).order_by(c.resource, c.lease_id)
        if resource is not None:
            query = query.where(c.resource == resource)
        return self._db.run(lambda conn: tuple(map(lease_of, conn.execute(query))), _RC)

    # ------------------------------------------------------------------ internals

    def _audit(self, conn: Connection, now: float, what: str, **detail: Any) -> None:
        conn.execute(insert(s.audit).values(at=now, actor=self.name, what=what, detail=detail))
        log.info("%s %s %s", self.name, what, detail)

    def _drop_lease(self, conn: Connection, row: Row[Any], now: float, what: str) -> None:
        conn.execute(delete(s.leases).where(s.leases.c.lease_id == row.lease_id))
        self._audit(conn, now, what, lease_id=row.lease_id, resource=row.resource,
                    holder=row.holder, granted_at=row.granted_at, expires_at=row.expires_at)


