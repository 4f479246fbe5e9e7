"""Leases in the records: granted to one holder per slot of capacity, renewed, released,
revoked on a last will and lapsed at their expiry, by the rules of the in-memory lease book;
on SQLite and PostgreSQL alike."""

from __future__ import annotations

import pytest

from polynav.errors import InvalidRequest
from polynav.fleet.records import FleetRecords
from polynav.leases.book import Lease
from polynav.leases.errors import LeaseNotHeld


def test_a_free_resource_is_granted_until_now_plus_duration(records: FleetRecords) -> None:
    lease = records.grant_lease("lift:A", "r1", now=10.0, duration=30.0)
    assert lease is not None
    assert (lease.resource, lease.holder, lease.granted_at, lease.expires_at) == (
        "lift:A", "r1", 10.0, 40.0)
    assert records.live_leases(10.0) == (lease,)


def test_a_held_resource_is_denied_to_another_and_returned_to_its_holder(
        records: FleetRecords) -> None:
    lease = records.grant_lease("lift:A", "r1", now=10.0, duration=30.0)
    assert records.grant_lease("lift:A", "r2", now=20.0, duration=30.0) is None
    assert records.grant_lease("lift:A", "r1", now=20.0, duration=99.0) == lease
    assert records.live_leases(20.0, "lift:A") == (lease,)


def test_a_lapsed_lease_frees_the_resource_at_its_expiry(records: FleetRecords) -> None:
    first = records.grant_lease("door:3", "r1", now=0.0, duration=5.0)
    assert records.grant_lease("door:3", "r2", now=4.999, duration=5.0) is None
    second = records.grant_lease("door:3", "r2", now=5.0, duration=5.0)
    assert first is not None and second is not None
    assert second.holder == "r2" and second.lease_id != first.lease_id
    assert records.live_leases(5.0) == (second,)


def test_capacity_admits_that_many_holders(records: FleetRecords) -> None:
    granted = [records.grant_lease("corridor:east", r, now=0.0, duration=10.0, capacity=2)
               for r in ("r1", "r2", "r3")]
    assert [g.holder if g else None for g in granted] == ["r1", "r2", None]
    assert records.release("corridor:east", "r1", now=1.0) is True
    third = records.grant_lease("corridor:east", "r3", now=1.0, duration=10.0, capacity=2)
    assert third is not None and third.holder == "r3"
    assert {lease.holder for lease in records.live_leases(1.0)} == {"r2", "r3"}


def test_renew_extends_a_live_lease_and_never_shortens_it(records: FleetRecords) -> None:
    lease = records.grant_lease("lift:A", "r1", now=0.0, duration=10.0)
    assert lease is not None
    renewed = records.renew("lift:A", "r1", now=8.0, duration=10.0)
    assert renewed == Lease(lease.lease_id, "lift:A", "r1", 0.0, 18.0)
    assert records.renew("lift:A", "r1", now=9.0, duration=1.0).expires_at == 18.0
    assert records.grant_lease("lift:A", "r2", now=17.0, duration=5.0) is None


def test_renew_after_the_expiry_is_refused(records: FleetRecords) -> None:
    records.grant_lease("lift:A", "r1", now=0.0, duration=10.0)
    with pytest.raises(LeaseNotHeld):
        records.renew("lift:A", "r1", now=10.0, duration=10.0)
    with pytest.raises(LeaseNotHeld):
        records.renew("lift:A", "r2", now=1.0, duration=10.0)


def test_release_frees_the_resource_once(records: FleetRecords) -> None:
    records.grant_lease("lift:A", "r1", now=0.0, duration=10.0)
    assert records.release("lift:A", "r2", now=1.0) is False
    assert records.release("lift:A", "r1", now=1.0) is True
    assert records.release("lift:A", "r1", now=1.0) is False
    lease = records.grant_lease("lift:A", "r2", now=1.0, duration=10.0)
    assert lease is not None and lease.holder == "r2"
    with pytest.raises(LeaseNotHeld):
        records.renew("lift:A", "r1", now=2.0, duration=10.0)


def test_release_of_a_lapsed_lease_is_no_release(records: FleetRecords) -> None:
    records.grant_lease("lift:A", "r1", now=0.0, duration=10.0)
    assert records.release("lift:A", "r1", now=12.0) is False
    assert [e.what for e in records.audit()][-1] == "lease.expired"


def test_revoke_all_takes_every_live_lease_of_a_lost_robot(records: FleetRecords) -> None:
    door = records.grant_lease("door:3", "r1", now=0.0, duration=50.0)
    lift = records.grant_lease("lift:A", "r1", now=0.0, duration=50.0)
    records.grant_lease("charger:1", "r1", now=0.0, duration=5.0)  # lapses before the will
    other = records.grant_lease("corridor:east", "r2", now=0.0, duration=50.0)
    assert records.revoke_all("r1", now=10.0) == (door, lift)
    assert records.revoke_all("r1", now=10.0) == ()
    assert records.live_leases(10.0) == (other,)
    taken = records.grant_lease("lift:A", "r3", now=10.0, duration=5.0)
    assert taken is not None and taken.holder == "r3"


def test_expire_removes_the_lapsed_leases_only(records: FleetRecords) -> None:
    short = records.grant_lease("door:1", "r1", now=0.0, duration=5.0)
    shorter = records.grant_lease("door:2", "r2", now=0.0, duration=3.0)
    long = records.grant_lease("door:3", "r3", now=0.0, duration=50.0)
    assert records.expire(5.0) == (shorter, short)
    assert records.expire(5.0) == ()
    assert records.live_leases(5.0) == (long,)


@pytest.mark.parametrize(("kwargs", "field"), [
    ({"duration": 0.0}, "duration"),
    ({"duration": -1.0}, "duration"),
    ({"duration": float("inf")}, "duration"),
    ({"duration": 5.0, "capacity": 0}, "capacity"),
    ({"duration": 5.0, "capacity": 1.5}, "capacity"),
])
def test_bad_lease_requests_are_refused_by_field(records: FleetRecords, kwargs: dict[str, float],
                                                 field: str) -> None:
    with pytest.raises(InvalidRequest) as caught:
        records.grant_lease("lift:A", "r1", now=0.0, **kwargs)  # type: ignore[arg-type]
    assert caught.value.field == field
    assert records.live_leases(0.0) == ()


@pytest.mark.parametrize(("resource", "holder"), [("", "r1"), ("lift:A", " "),
                                                  ("x" * 201, "r1")])
def test_bad_names_are_refused(records: FleetRecords, resource: str, holder: str) -> None:
    with pytest.raises(InvalidRequest):
        records.grant_lease(resource, holder, now=0.0, duration=5.0)
