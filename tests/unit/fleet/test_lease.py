"""The lease book: grants, renewals, releases, expiries, FIFO queues and bounded waits."""

from __future__ import annotations

import pytest

from polynav.errors import ConfigError, InvalidRequest
from polynav.leases.book import Lease, LeaseBook, LeaseBookConfig, LeaseEventKind, same_way
from polynav.leases.errors import LeaseNotHeld, LeaseRefused

K = LeaseEventKind


def kinds(book: LeaseBook) -> list[tuple[LeaseEventKind, str, str]]:
    return [(e.kind, e.resource, e.holder) for e in book.take_events()]


@pytest.fixture
def book() -> LeaseBook:
    return LeaseBook(LeaseBookConfig(default_duration=10.0, max_duration=60.0, max_wait=30.0,
                                     max_hold=40.0))


def test_free_resource_is_granted_at_once_with_an_expiry(book: LeaseBook) -> None:
    lease = book.request("lift:A", "r1", now=5.0)
    assert lease == Lease(lease_id=1, resource="lift:A", holder="r1", granted_at=5.0,
                          expires_at=15.0)
    assert book.lease("lift:A", "r1") == lease
    assert kinds(book) == [(K.GRANTED, "lift:A", "r1")]


def test_asking_again_returns_the_same_lease_unchanged(book: LeaseBook) -> None:
    first = book.request("lift:A", "r1", now=0.0)
    again = book.request("lift:A", "r1", now=3.0, duration=50.0)
    assert again == first


def test_second_holder_is_queued_and_granted_when_the_first_releases(book: LeaseBook) -> None:
    book.request("door:1", "r1", now=0.0)
    assert book.request("door:1", "r2", now=1.0, duration=20.0) is None
    assert book.position("door:1", "r2") == 0
    assert book.release("door:1", "r1", now=4.0) is True
    lease = book.lease("door:1", "r2")
    assert lease is not None and lease.granted_at == 4.0 and lease.expires_at == 24.0
    # The waiter learns of its grant by asking again: the same lease comes back.
    assert book.request("door:1", "r2", now=5.0) == lease
    assert kinds(book) == [(K.GRANTED, "door:1", "r1"), (K.QUEUED, "door:1", "r2"),
                           (K.RELEASED, "door:1", "r1"), (K.GRANTED, "door:1", "r2")]


def test_waiters_are_served_in_the_order_they_came(book: LeaseBook) -> None:
    book.request("corridor:east", "r1", now=0.0)
    for i, holder in enumerate(["r3", "r2", "r4"]):
        book.request("corridor:east", holder, now=1.0 + i)
    served = []
    t = 5.0
    for _ in range(3):
        (current,) = book.leases("corridor:east")
        book.release("corridor:east", current.holder, now=t)
        served.append(book.leases("corridor:east")[0].holder)
        t += 1.0
    assert served == ["r3", "r2", "r4"]


def test_queues_list_only_the_resources_someone_waits_for_in_line_order(
        book: LeaseBook) -> None:
    book.request("door:1", "r1", now=0.0)
    book.request("door:2", "r1", now=0.0)
    book.request("door:1", "r3", now=1.0)
    book.request("door:1", "r2", now=2.0)
    assert {name: [w.holder for w in q] for name, q in book.queues().items()} == {
        "door:1": ["r3", "r2"]}
    book.release("door:1", "r1", now=3.0)
    assert [w.holder for w in book.queues()["door:1"]] == ["r2"]
    book.release("door:1", "r3", now=4.0)
    assert book.queues() == {}


def test_newcomer_never_overtakes_a_waiter_even_when_capacity_frees_between_calls(
        book: LeaseBook) -> None:
    book.request("charger:1", "r1", now=0.0)
    book.request("charger:1", "r2", now=1.0)
    # r1's lease lapses at t=10; r2 is granted then, before r3's request is looked at.
    assert book.request("charger:1", "r3", now=11.0) is None
    assert [le.holder for le in book.leases("charger:1")] == ["r2"]
    assert book.position("charger:1", "r3") == 0


def test_lease_not_renewed_expires_and_the_next_waiter_is_granted(book: LeaseBook) -> None:
    book.request("lift:A", "r1", now=0.0)
    book.request("lift:A", "r2", now=2.0)
    book.tick(9.999)
    assert book.lease("lift:A", "r1") is not None
    book.tick(10.0)
    assert book.lease("lift:A", "r1") is None
    lease = book.lease("lift:A", "r2")
    assert lease is not None and lease.granted_at == 10.0
    events = book.take_events()
    expired = [e for e in events if e.kind is K.EXPIRED]
    assert len(expired) == 1 and expired[0].holder == "r1" and expired[0].at == 10.0


def test_renewal_extends_the_lease_and_keeps_its_id(book: LeaseBook) -> None:
    first = book.request("lift:A", "r1", now=0.0)
    assert first is not None
    renewed = book.renew("lift:A", "r1", now=8.0, duration=20.0)
    assert renewed.lease_id == first.lease_id
    assert renewed.granted_at == 0.0 and renewed.expires_at == 28.0
    book.tick(27.0)
    assert book.lease("lift:A", "r1") == renewed


def test_renewal_never_shortens_a_lease(book: LeaseBook) -> None:
    book.request("lift:A", "r1", now=0.0, duration=50.0)
    assert book.renew("lift:A", "r1", now=1.0, duration=5.0).expires_at == 50.0


def test_renewal_after_expiry_is_refused_as_lost(book: LeaseBook) -> None:
    book.request("lift:A", "r1", now=0.0)
    with pytest.raises(LeaseNotHeld) as err:
        book.renew("lift:A", "r1", now=10.0)
    assert err.value.resource == "lift:A" and err.value.holder == "r1"


def test_renewal_of_a_lease_never_granted_is_refused(book: LeaseBook) -> None:
    book.request("lift:A", "r1", now=0.0)
    with pytest.raises(LeaseNotHeld):
        book.renew("lift:A", "r2", now=1.0)
    with pytest.raises(LeaseNotHeld):
        book.renew("lift:B", "r1", now=1.0)


def test_waiter_past_its_deadline_leaves_the_queue_and_is_never_granted(book: LeaseBook) -> None:
    book.request("lift:A", "r1", now=0.0, duration=60.0)
    book.request("lift:A", "r2", now=1.0, max_wait=5.0)
    book.tick(6.0)
    assert book.waiters("lift:A") == ()
    book.release("lift:A", "r1", now=7.0)
    assert book.leases("lift:A") == ()
    timed_out = [e for e in book.take_events() if e.kind is K.WAIT_TIMED_OUT]
    assert [(e.holder, e.at) for e in timed_out] == [("r2", 6.0)]


def test_a_timed_out_waiter_asking_again_at_once_keeps_its_place(book: LeaseBook) -> None:
    """Told to give up, r2 asks again at once: still ahead of r3 and r4, who came later."""
    book.request("lift:A", "r1", now=0.0, duration=60.0)
    book.request("lift:A", "r2", now=1.0, max_wait=5.0)
    book.request("lift:A", "r3", now=2.0)
    book.request("lift:A", "r4", now=3.0)
    book.tick(6.5)
    assert [w.holder for w in book.waiters("lift:A")] == ["r3", "r4"]
    assert book.request("lift:A", "r2", now=7.0) is None
    assert [w.holder for w in book.waiters("lift:A")] == ["r2", "r3", "r4"]
    assert book.waiters("lift:A")[0].deadline == 37.0  # a fresh deadline
    book.release("lift:A", "r1", now=8.0)
    assert [lease.holder for lease in book.leases("lift:A")] == ["r2"]


def test_asking_again_long_after_timing_out_goes_to_the_back(book: LeaseBook) -> None:
    book.request("lift:A", "r1", now=0.0, duration=60.0)
    book.request("lift:A", "r2", now=1.0, max_wait=5.0)
    book.request("lift:A", "r3", now=2.0)
    book.tick(6.5)
    book.request("lift:A", "r2", now=6.0 + book.config.reask_grace + 1.0)
    assert [w.holder for w in book.waiters("lift:A")] == ["r3", "r2"]


def test_a_waiter_that_left_the_queue_and_asks_again_at_once_keeps_its_place(
        book: LeaseBook) -> None:
    """r2 gives its place up (its path briefly put the zone out of reach) and asks again four
    seconds later: still ahead of r3 and r4, who came after it (issue 36)."""
    book.request("zone:c", "r1", now=0.0, duration=60.0)
    book.request("zone:c", "r2", now=1.0)
    book.request("zone:c", "r3", now=2.0)
    book.request("zone:c", "r4", now=3.0)
    assert book.release("zone:c", "r2", now=10.0)
    assert [w.holder for w in book.waiters("zone:c")] == ["r3", "r4"]
    assert book.request("zone:c", "r2", now=14.0) is None
    assert [w.holder for w in book.waiters("zone:c")] == ["r2", "r3", "r4"]
    assert book.waiters("zone:c")[0].deadline == 44.0  # a fresh deadline
    # Long after leaving, it is a newcomer: at the back.
    assert book.release("zone:c", "r2", now=15.0)
    assert book.request("zone:c", "r2", now=15.0 + book.config.reask_grace + 1.0) is None
    assert [w.holder for w in book.waiters("zone:c")] == ["r3", "r4", "r2"]


def test_a_waiter_back_at_the_head_going_the_flows_way_is_let_in_at_once() -> None:
    """r2 (east) timed out behind r0; r3 (east) got in after r0; r4 (west) waits for the east
    flow to drain. r2 asks again at once: older than r4, and going east, it joins r3."""
    book = LeaseBook(LeaseBookConfig(max_wait=100.0))
    book.request("zone:c", "r0", now=0.0)
    book.request("zone:c", "r2", now=1.0, flow="EE", max_wait=5.0)
    book.request("zone:c", "r3", now=1.5, flow="EE")
    book.request("zone:c", "r4", now=2.0, flow="WW")
    book.tick(6.0)  # r2 gave up
    book.release("zone:c", "r0", now=6.2)
    assert [lease.holder for lease in book.leases("zone:c")] == ["r3"]
    lease = book.request("zone:c", "r2", now=7.0, flow="EE")
    assert lease is not None and lease.holder == "r2"
    assert [w.holder for w in book.waiters("zone:c")] == ["r4"]


def test_max_wait_is_capped_by_the_books_limit(book: LeaseBook) -> None:
    book.request("lift:A", "r1", now=0.0, duration=60.0)
    book.request("lift:A", "r2", now=0.0, max_wait=1000.0)
    assert book.waiters("lift:A")[0].deadline == 30.0


def test_holder_cannot_renew_past_max_hold_while_others_wait(book: LeaseBook) -> None:
    book.request("corridor:east", "r1", now=0.0)
    t = 0.0
    while t < 35.0:
        t += 5.0
        book.renew("corridor:east", "r1", now=t)
    book.request("corridor:east", "r2", now=t)
    book.renew("corridor:east", "r1", now=39.0)
    with pytest.raises(LeaseRefused):
        book.renew("corridor:east", "r1", now=40.0)
    # Refused, it still holds until its last expiry; then r2 is granted.
    book.tick(49.0)
    assert book.lease("corridor:east", "r2") is not None


def test_alone_a_holder_may_renew_for_ever(book: LeaseBook) -> None:
    book.request("charger:1", "r1", now=0.0)
    for t in range(5, 500, 5):
        book.renew("charger:1", "r1", now=float(t))
    assert book.lease("charger:1", "r1") is not None


def test_every_waiter_is_granted_or_told_to_give_up_within_a_bound(book: LeaseBook) -> None:
    """A holder that renews as often as it may and waiters that keep asking: no one waits longer
    than max_wait, and the holder cannot keep the resource past max_hold + max_duration."""
    book.request("lift:A", "r0", now=0.0)
    outcome: dict[str, str] = {}
    for t10 in range(1, 2000):
        t = t10 / 10.0
        if t10 % 50 == 0 and book.lease("lift:A", "r0") is not None:
            try:
                book.renew("lift:A", "r0", now=t)
            except LeaseRefused:
                pass
        if t10 in (10, 20, 30):
            book.request("lift:A", f"w{t10}", now=t)
        book.tick(t)
        for e in book.take_events():
            if e.holder != "r0" and e.kind in (K.GRANTED, K.WAIT_TIMED_OUT):
                outcome.setdefault(e.holder, f"{e.kind.value}@{e.at}")
                if e.kind is K.GRANTED:
                    book.release("lift:A", e.holder, now=t)
    assert set(outcome) == {"w10", "w20", "w30"}
    assert all(float(v.split("@")[1]) <= 3.0 + 30.0 for v in outcome.values())


def test_release_twice_is_harmless_and_release_cancels_a_wait(book: LeaseBook) -> None:
    book.request("door:1", "r1", now=0.0)
    book.request("door:1", "r2", now=0.0)
    book.request("door:1", "r3", now=0.0)
    assert book.release("door:1", "r2", now=1.0) is True
    assert book.position("door:1", "r3") == 0
    assert book.release("door:1", "r1", now=2.0) is True
    assert book.release("door:1", "r1", now=2.0) is False
    assert book.release("nowhere", "r1", now=2.0) is False
    assert [le.holder for le in book.leases("door:1")] == ["r3"]
    assert (K.WAIT_CANCELLED, "door:1", "r2") in kinds(book)


def test_capacity_lets_several_hold_at_once(book: LeaseBook) -> None:
    book.set_capacity("lift:A", 2)
    assert book.request("lift:A", "r1", now=0.0) is not None
    assert book.request("lift:A", "r2", now=0.0) is not None
    assert book.request("lift:A", "r3", now=0.0) is None
    with pytest.raises(InvalidRequest):
        book.set_capacity("lift:A", 1)
    book.release("lift:A", "r1", now=1.0)
    assert {le.holder for le in book.leases("lift:A")} == {"r2", "r3"}


def test_release_all_frees_every_lease_and_wait_of_a_holder(book: LeaseBook) -> None:
    book.request("a", "r1", now=0.0)
    book.request("b", "r1", now=0.0)
    book.request("c", "r2", now=0.0)
    book.request("c", "r1", now=0.0)
    assert book.release_all("r1", now=1.0) == ("a", "b", "c")
    assert book.held_by("r1") == ()
    assert book.waiters("c") == ()


def test_held_by_and_next_deadline(book: LeaseBook) -> None:
    assert book.next_deadline() is None
    book.request("b", "r1", now=0.0, duration=20.0)
    book.request("a", "r1", now=0.0, duration=30.0)
    book.request("a", "r2", now=1.0, max_wait=4.0)
    assert [le.resource for le in book.held_by("r1")] == ["a", "b"]
    assert book.next_deadline() == 5.0
    assert book.resources() == ("a", "b")


@pytest.mark.parametrize("kwargs, field", [
    ({"resource": "", "holder": "r1"}, "resource"),
    ({"resource": "  ", "holder": "r1"}, "resource"),
    ({"resource": "a", "holder": ""}, "holder"),
    ({"resource": "a", "holder": "r1", "duration": 0.0}, "duration"),
    ({"resource": "a", "holder": "r1", "duration": -1.0}, "duration"),
    ({"resource": "a", "holder": "r1", "duration": 61.0}, "duration"),
    ({"resource": "a", "holder": "r1", "duration": float("nan")}, "duration"),
    ({"resource": "a", "holder": "r1", "max_wait": 0.0}, "max_wait"),
])
def test_bad_requests_are_refused_without_changing_the_book(
        book: LeaseBook, kwargs: dict[str, object], field: str) -> None:
    with pytest.raises(InvalidRequest) as err:
        book.request(now=0.0, **kwargs)  # type: ignore[arg-type]
    assert err.value.field == field
    assert book.resources() == () and book.take_events() == []


def test_time_running_backwards_is_refused(book: LeaseBook) -> None:
    book.tick(10.0)
    with pytest.raises(InvalidRequest) as err:
        book.request("a", "r1", now=9.0)
    assert err.value.field == "now"


@pytest.mark.parametrize("kwargs", [
    {"default_duration": 0.0}, {"max_wait": -1.0}, {"max_hold": 0.0},
    {"default_duration": 100.0, "max_duration": 50.0},
])
def test_bad_config_names_the_key(kwargs: dict[str, float]) -> None:
    with pytest.raises(ConfigError) as err:
        LeaseBookConfig(**kwargs)
    assert err.value.key.startswith("fleet.lease.")


def test_holders_going_the_same_way_share_a_passage(book: LeaseBook) -> None:
    assert book.request("zone:c", "r1", now=0.0, flow="E") is not None
    second = book.request("zone:c", "r2", now=1.0, flow="E")
    assert second is not None and second.flow == "E"
    assert {lease.holder for lease in book.leases("zone:c")} == {"r1", "r2"}


def test_one_going_the_other_way_waits_until_the_flow_has_drained(book: LeaseBook) -> None:
    book.request("zone:c", "r1", now=0.0, flow="E")
    book.request("zone:c", "r2", now=0.5, flow="E")
    assert book.request("zone:c", "r3", now=1.0, flow="W") is None
    # A newcomer of the flow inside does not overtake the one waiting for the other way.
    assert book.request("zone:c", "r4", now=1.5, flow="E") is None
    book.release("zone:c", "r1", now=2.0)
    assert book.lease("zone:c", "r3") is None
    book.release("zone:c", "r2", now=3.0)
    assert book.lease("zone:c", "r3") is not None
    assert book.lease("zone:c", "r4") is None  # now r4 waits for the westward one
    book.release("zone:c", "r3", now=4.0)
    assert book.lease("zone:c", "r4") is not None


def test_waiters_of_one_flow_are_let_in_together(book: LeaseBook) -> None:
    book.request("zone:c", "r1", now=0.0, flow="W")
    book.request("zone:c", "r2", now=1.0, flow="E")
    book.request("zone:c", "r3", now=1.5, flow="E")
    book.request("zone:c", "r4", now=2.0, flow="W")
    book.release("zone:c", "r1", now=3.0)
    assert [lease.holder for lease in book.leases("zone:c")] == ["r2", "r3"]
    assert [w.holder for w in book.waiters("zone:c")] == ["r4"]


def test_holders_whose_ways_never_head_opposite_share_and_others_wait(book: LeaseBook) -> None:
    """Out of a door and east ("NE") goes with east along ("EE"): never against each other.
    Into that door from the west ("ES") heads south where the first heads north: it waits."""
    assert book.request("zone:c", "r1", now=0.0, flow="EE") is not None
    assert book.request("zone:c", "r2", now=1.0, flow="NE") is not None
    assert book.request("zone:c", "r3", now=2.0, flow="ES") is None
    book.release("zone:c", "r2", now=3.0)
    assert book.lease("zone:c", "r3") is not None  # with r1 alone (east) it goes in
    # Up one door, along and down another ("NES") goes against itself: alone, always.
    book.release("zone:c", "r1", now=4.0)
    book.release("zone:c", "r3", now=4.0)
    assert book.request("zone:c", "r4", now=5.0, flow="NES") is not None
    assert book.request("zone:c", "r5", now=6.0, flow="NES") is None


@pytest.mark.parametrize(("a", "b", "together"), [
    ("EE", "EE", True), ("EE", "WW", False), ("NE", "EE", True), ("NE", "ES", False),
    ("NWN", "WW", True), ("NWN", "NEN", False), ("NWS", "NWS", False), ("up", "up", True),
    ("up", "down", False), ("E", "up", False),
])
def test_same_way(a: str, b: str, together: bool) -> None:
    assert same_way(a, b) is together and same_way(b, a) is together


def test_when_the_head_goes_in_those_behind_going_its_way_go_with_it(book: LeaseBook) -> None:
    """r2 (west) waits for r1 (east) to come out; r3 (east, behind r2) may not join r1 then.
    r4 (west) and r5 (no flow) wait behind r3. When r2 goes in, r4 goes with it, passing r3,
    who would wait for r2 anyway; r5 goes alone, in its turn."""
    book.request("zone:c", "r1", now=0.0, flow="EE")
    book.request("zone:c", "r2", now=1.0, flow="WW")
    book.request("zone:c", "r3", now=2.0, flow="EE")
    book.request("zone:c", "r4", now=3.0, flow="NW")
    book.request("zone:c", "r5", now=4.0)
    assert [lease.holder for lease in book.leases("zone:c")] == ["r1"]
    book.release("zone:c", "r1", now=5.0)
    assert [lease.holder for lease in book.leases("zone:c")] == ["r2", "r4"]
    assert [w.holder for w in book.waiters("zone:c")] == ["r3", "r5"]
    book.release("zone:c", "r2", now=6.0)
    assert book.lease("zone:c", "r3") is None  # r4 (west) is still inside
    book.release("zone:c", "r4", now=7.0)
    assert [lease.holder for lease in book.leases("zone:c")] == ["r3"]
    assert [w.holder for w in book.waiters("zone:c")] == ["r5"]


def test_a_holder_without_a_flow_keeps_the_passage_to_itself(book: LeaseBook) -> None:
    book.request("zone:c", "r1", now=0.0)
    assert book.request("zone:c", "r2", now=1.0, flow="E") is None
    book.release("zone:c", "r1", now=2.0)
    assert book.lease("zone:c", "r2") is not None
    assert book.request("zone:c", "r3", now=3.0) is None  # no flow: it waits for its own turn


def test_an_empty_flow_is_refused(book: LeaseBook) -> None:
    with pytest.raises(InvalidRequest):
        book.request("zone:c", "r1", now=0.0, flow=" ")
    assert book.leases("zone:c") == ()
