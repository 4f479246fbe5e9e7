"""A fleet manager's tick writes in one transaction what it did for many robots: claims, orders
sent, confirmations and ends; each as the one-at-a-time call would, on SQLite and PostgreSQL."""

from __future__ import annotations

from polynav.fleet.records import FleetRecords, MissionState, OrderState

A = [{"point": "lobby"}]


def test_claims_in_one_go_take_the_named_missions_and_leave_out_the_taken(
        records: FleetRecords) -> None:
    for k in (1, 2, 3):
        records.add_mission(A, now=1.0, mission_id=f"m{k}")
    records.claim_mission("r9", now=1.5, mission_id="m2")
    got = records.claim_missions([("r1", "m3"), ("r2", "m2"), ("r3", "m1")], now=2.0)
    assert [(robot, m.mission_id, m.attempts) for robot, m in got] == [
        ("r1", "m3", 1), ("r3", "m1", 1)]
    assert records.mission("m2").robot == "r9"
    assert records.missions(MissionState.QUEUED) == ()


def test_orders_sent_confirmed_and_missions_done_in_one_go(records: FleetRecords) -> None:
    for k in (1, 2, 3):
        records.add_mission(A, now=1.0, mission_id=f"m{k}")
        records.claim_mission(f"r{k}", now=1.0, mission_id=f"m{k}")
    records.orders_sent([(f"m{k}-1", 0, f"r{k}", f"m{k}") for k in (1, 2, 3)], now=2.0)
    records.orders_sent([("m1-1", 0, "r1", "m1")], now=3.0)  # a re-send counts
    assert [records.order(f"m{k}-1", 0).sends for k in (1, 2, 3)] == [2, 1, 1]
    records.cancel_mission("m3", now=3.5)
    ended = records.progress(confirmed=[("m1-1", 0), ("m2-1", 0)], done=["m1", "m3"],
                             now=4.0)
    assert ended == ("m1",)  # m3 was cancelled meanwhile: left as it is
    assert [records.order(f"m{k}-1", 0).state for k in (1, 2, 3)] == [
        OrderState.CONFIRMED, OrderState.CONFIRMED, OrderState.SENT]
    assert [records.mission(f"m{k}").state for k in (1, 2, 3)] == [
        MissionState.DONE, MissionState.ACTIVE, MissionState.CANCELLED]
    assert records.progress(confirmed=[], done=["m1"], now=5.0) == ("m1",)  # again: no change
    whats = [e.what for e in records.audit()]
    assert whats.count("order.sent") == 3 and whats.count("order.resent") == 1
    assert whats.count("order.confirmed") == 2 and whats.count("mission.done") == 1
