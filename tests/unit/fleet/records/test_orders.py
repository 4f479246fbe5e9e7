"""Orders sent to robots: unconfirmed ones are found to be sent again, a state confirms them,
a later update supersedes them; on SQLite and PostgreSQL alike."""

from __future__ import annotations

import pytest

from polynav.errors import InvalidRequest, NotFound
from polynav.fleet.records import FleetRecords, OrderState


def test_a_sent_order_is_unconfirmed_once_older_than_the_limit(records: FleetRecords) -> None:
    sent = records.order_sent("r1-1", 0, robot="r1", now=10.0, mission="m1")
    assert (sent.state, sent.sent_at, sent.confirmed_at, sent.sends, sent.mission) == (
        OrderState.SENT, 10.0, None, 1, "m1")
    assert records.unconfirmed_orders(older_than=10.0) == ()
    assert records.unconfirmed_orders(older_than=10.5) == (sent,)


def test_a_confirmed_order_is_not_sent_again(records: FleetRecords) -> None:
    records.order_sent("r1-1", 0, robot="r1", now=10.0)
    assert records.order_confirmed("r1-1", 0, now=11.0) == 1
    assert records.order_confirmed("r1-1", 0, now=12.0) == 0
    assert records.unconfirmed_orders(older_than=99.0) == ()
    confirmed = records.order("r1-1", 0)
    assert (confirmed.state, confirmed.confirmed_at) == (OrderState.CONFIRMED, 11.0)


def test_sending_again_moves_sent_at_and_counts(records: FleetRecords) -> None:
    records.order_sent("r1-1", 0, robot="r1", now=10.0)
    again = records.order_sent("r1-1", 0, robot="r1", now=15.0)
    assert (again.sent_at, again.sends, again.state) == (15.0, 2, OrderState.SENT)
    assert records.unconfirmed_orders(older_than=12.0) == ()


def test_a_later_update_supersedes_an_unconfirmed_earlier_one(records: FleetRecords) -> None:
    records.order_sent("r1-1", 0, robot="r1", now=10.0)
    records.order_sent("r1-1", 1, robot="r1", now=11.0)
    assert records.order("r1-1", 0).state is OrderState.SUPERSEDED
    assert [(o.order_id, o.update_id) for o in records.unconfirmed_orders(99.0)] == [
        ("r1-1", 1)]


def test_a_state_naming_a_later_update_confirms_the_earlier_ones(
        records: FleetRecords) -> None:
    records.order_sent("r1-1", 0, robot="r1", now=10.0)
    records.order_sent("r2-1", 0, robot="r2", now=10.0)
    records.order_sent("r1-1", 2, robot="r1", now=11.0)
    assert records.order_confirmed("r1-1", 5, now=12.0) == 1
    assert [o.order_id for o in records.unconfirmed_orders(99.0)] == ["r2-1"]


def test_an_order_never_sent_is_not_found(records: FleetRecords) -> None:
    with pytest.raises(NotFound):
        records.order("nope", 0)


@pytest.mark.parametrize("update_id", [-1, 1.0, True, "0"])
def test_bad_update_ids_are_refused(records: FleetRecords, update_id: object) -> None:
    with pytest.raises(InvalidRequest) as caught:
        records.order_sent("o", update_id, robot="r1", now=0.0)  # type: ignore[arg-type]
    assert caught.value.field == "update_id"
