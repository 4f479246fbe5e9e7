"""The audit trail: every change, in the transaction that makes it, by the fleet manager that
made it; nothing for a request that changed nothing."""

from __future__ import annotations

import pytest

from polynav.errors import InvalidRequest
from polynav.fleet.records import FleetRecords
from polynav.leases.errors import LeaseNotHeld


def test_every_change_is_audited_in_order_with_its_detail(records: FleetRecords) -> None:
    records.add_mission([{"point": "lab"}], now=1.0, mission_id="m1")
    records.claim_mission("r1", now=2.0)
    lease = records.grant_lease("lift:A", "r1", now=3.0, duration=10.0)
    assert lease is not None
    records.renew("lift:A", "r1", now=4.0, duration=20.0)
    records.order_sent("r1-1", 0, robot="r1", now=5.0, mission="m1")
    records.order_confirmed("r1-1", 0, now=6.0)
    records.revoke_all("r1", now=7.0)
    records.requeue_robot("r1", now=7.0)
    entries = records.audit()
    assert [(e.at, e.what) for e in entries] == [
        (1.0, "mission.added"), (2.0, "mission.claimed"), (3.0, "lease.granted"),
        (4.0, "lease.renewed"), (5.0, "order.sent"), (6.0, "order.confirmed"),
        (7.0, "lease.revoked"), (7.0, "mission.requeued")]
    assert {e.actor for e in entries} == {"fm-test"}
    assert entries[2].detail == {"lease_id": lease.lease_id, "resource": "lift:A",
                                 "holder": "r1", "slot": 0, "granted_at": 3.0,
                                 "expires_at": 13.0}
    assert entries[6].detail["expires_at"] == 24.0
    assert entries[7].detail == {"mission": "m1", "robot": "r1"}
    ids = [e.entry_id for e in entries]
    assert ids == sorted(ids) and len(set(ids)) == len(ids)


def test_requests_that_change_nothing_leave_no_entry(records: FleetRecords) -> None:
    records.grant_lease("lift:A", "r1", now=0.0, duration=10.0)
    before = records.audit()
    assert records.grant_lease("lift:A", "r2", now=1.0, duration=10.0) is None
    assert records.grant_lease("lift:A", "r1", now=1.0, duration=10.0) is not None
    assert records.release("lift:A", "r2", now=1.0) is False
    assert records.claim_mission("r1", now=1.0) is None
    with pytest.raises(LeaseNotHeld):
        records.renew("door:1", "r1", now=1.0, duration=1.0)
    assert records.audit() == before


def test_audit_pages_after_an_id(records: FleetRecords) -> None:
    for k in range(5):
        records.note("fleet.started", now=float(k), k=k)
    first = records.audit(limit=2)
    rest = records.audit(after=first[-1].entry_id)
    assert [e.detail["k"] for e in first + rest] == [0, 1, 2, 3, 4]


def test_a_note_must_be_json(records: FleetRecords) -> None:
    with pytest.raises(InvalidRequest):
        records.note("x", now=0.0, bad=object())
    assert records.audit() == ()
