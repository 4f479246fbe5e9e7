"""What a lease book asks of a ledger that has the last word on its grants.

A :class:`~polynav.leases.book.LeaseBook` is one process's memory. When several processes lend
the same resources (two fleet managers on one site), something they share must decide who
gets a lift car: a :class:`LeaseLedger`, in practice the fleet manager's database
(:mod:`polynav.fleet.manager.ledger`). The book keeps its queue, flows and time-outs, and asks
the ledger before each grant; what the ledger refuses, the book does not grant.
"""

from __future__ import annotations

from typing import Protocol


class LeaseLedger(Protocol):
    """The shared record of leases a :class:`~polynav.leases.book.LeaseBook` defers to."""

    def take(self, resource: str, holder: str, *, now: float, duration: float, capacity: int,
             flow: str | None) -> bool:
        """Record a grant of ``resource`` to ``holder`` until ``now + duration`` [s]; False
        when the ledger refuses it (the resource is full there, or the ledger cannot be
        reached now). A holder already holding it there is agreed to."""
        ...

    def renewed(self, resource: str, holder: str, *, now: float, duration: float) -> None:
        """Extend ``holder``'s lease to at least ``now + duration`` [s].

        Raises:
            LeaseNotHeld: the ledger has no live lease of ``holder`` on ``resource``.
        """
        ...

    def dropped(self, resource: str, holder: str, *, now: float) -> None:
        """``holder``'s lease on ``resource`` is given back (released or lapsed)."""
        ...
