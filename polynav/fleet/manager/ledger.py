"""The fleet manager's records as the lease book's ledger: the database decides every grant.

:class:`RecordsLedger` is the :class:`~polynav.leases.interface.LeaseLedger` a fleet
manager's :class:`~polynav.leases.book.LeaseBook` defers to. A grant is made only once
:meth:`~polynav.fleet.records.FleetRecords.grant_lease` has taken one of the resource's slots
in the database, so two fleet managers sharing one PostgreSQL never both hand out a lift car:
the one whose transaction loses is refused, and its book keeps the robot queued and asks
again next tick.

A lease with a *flow* (robots going the same way through a corridor share it beyond its
capacity, :mod:`polynav.leases.book`) takes a slot among :data:`FLOW_SLOTS`: the database
records it (it is revoked with its robot and seen by the other managers) but does not judge
directions, which stay the book's (docs/decisions.md, "fleet manager: leases").

A database that cannot be reached refuses: no lease is granted on a guess. Renewals and
leases given back are written through; a failure there is logged, since the lease lapses in
the database by itself at its expiry.
"""

from __future__ import annotations

import logging

from polynav.fleet.records import FleetRecords, FleetRecordsError
from polynav.leases.errors import LeaseNotHeld

log = logging.getLogger(__name__)

FLOW_SLOTS = 64
"""How many holders of flows may share one resource in the database."""


class RecordsLedger:
    """Leases written to the fleet's records before they are granted (module docstring)."""

    def __init__(self, records: FleetRecords) -> None:
        self.records = records
        self.refused = 0

    def take(self, resource: str, holder: str, *, now: float, duration: float, capacity: int,
             flow: str | None) -> bool:
        try:
            lease = self.records.grant_lease(
                resource, holder, now=now, duration=duration,
                capacity=capacity if flow is None else max(capacity, FLOW_SLOTS))
        except FleetRecordsError as exc:
            log.warning("lease on %s for %s not granted: records unreachable (%s)",
                        resource, holder, exc)
            self.refused += 1
            return False
        if lease is None:
            log.debug("lease on %s for %s refused by the records (held elsewhere)",
                      resource, holder)
            self.refused += 1
            return False
        return True

    def renewed(self, resource: str, holder: str, *, now: float, duration: float) -> None:
        try:
            self.records.renew(resource, holder, now=now, duration=duration)
        except FleetRecordsError as exc:
            log.warning("renewal of %s for %s not recorded: %s", resource, holder, exc)
        except LeaseNotHeld:
            log.warning("renewal of %s for %s refused: the records no longer hold it",
                        resource, holder)
            raise

    def dropped(self, resource: str, holder: str, *, now: float) -> None:
        try:
            self.records.release(resource, holder, now=now)
        except FleetRecordsError as exc:
            log.warning("release of %s by %s not recorded (it lapses there): %s",
                        resource, holder, exc)
