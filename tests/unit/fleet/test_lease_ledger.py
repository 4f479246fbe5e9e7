"""The lease book with a ledger that has the last word on its grants (the fleet manager's
database, here a shared dict standing for it): refused grants wait in line and are asked
again at each tick; renewals, releases and expiries reach the ledger."""

from __future__ import annotations

import pytest

from polynav.leases.book import LeaseBook, LeaseBookConfig
from polynav.leases.errors import LeaseNotHeld


class SharedLedger:
    """Resource -> holder, shared by books standing for two fleet managers."""

    def __init__(self) -> None:
        self.holders: dict[str, str] = {}
        self.log: list[tuple[str, str, str]] = []

    def take(self, resource: str, holder: str, *, now: float, duration: float, capacity: int,
             flow: str | None) -> bool:
        taken = self.holders.setdefault(resource, holder) == holder
        self.log.append(("take" if taken else "refused", resource, holder))
        return taken

    def renewed(self, resource: str, holder: str, *, now: float, duration: float) -> None:
        if self.holders.get(resource) != holder:
            raise LeaseNotHeld(resource, holder, "not in the ledger")
        self.log.append(("renew", resource, holder))

    def dropped(self, resource: str, holder: str, *, now: float) -> None:
        if self.holders.get(resource) == holder:
            del self.holders[resource]
        self.log.append(("drop", resource, holder))


@pytest.fixture
def ledger() -> SharedLedger:
    return SharedLedger()


def test_a_grant_the_ledger_refuses_waits_first_in_line_and_goes_once_agreed(
        ledger: SharedLedger) -> None:
    one, two = LeaseBook(ledger=ledger), LeaseBook(ledger=ledger)
    assert one.request("lift:A", "a", now=0.0) is not None
    assert two.request("lift:A", "b", now=0.0) is None  # its own book was free
    assert two.request("lift:A", "c", now=0.5) is None
    assert [w.holder for w in two.waiters("lift:A")] == ["b", "c"]
    two.tick(1.0)
    assert two.leases("lift:A") == ()  # still held in the ledger
    assert one.release("lift:A", "a", now=2.0)
    two.tick(2.5)
    assert [lease.holder for lease in two.leases("lift:A")] == ["b"]
    assert [w.holder for w in two.waiters("lift:A")] == ["c"]
    assert ledger.holders == {"lift:A": "b"}
    assert ("drop", "lift:A", "a") in ledger.log


def test_expiry_and_renewal_reach_the_ledger_and_a_lease_it_lost_is_lost(
        ledger: SharedLedger) -> None:
    book = LeaseBook(LeaseBookConfig(default_duration=10.0), ledger=ledger)
    book.request("door:1", "a", now=0.0)
    book.renew("door:1", "a", now=5.0)
    assert ("renew", "door:1", "a") in ledger.log
    book.tick(20.0)
    assert ledger.holders == {} and ("drop", "door:1", "a") in ledger.log
    book.request("door:1", "a", now=21.0)
    del ledger.holders["door:1"]  # revoked elsewhere (its robot's last will, another manager)
    with pytest.raises(LeaseNotHeld):
        book.renew("door:1", "a", now=22.0)
    assert book.lease("door:1", "a") is None
