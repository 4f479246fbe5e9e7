"""The per-connection outbox every dialect server writes through: replies first, bounded."""

from __future__ import annotations

import asyncio

import pytest

from polynav.protocols.outbox import Outbox, OutboxClosed


def _drain(box: Outbox[str]) -> list[str]:
    async def take() -> list[str]:
        out = []
        while box.pending:
            out.append(await box.get())
        return out

    return asyncio.run(take())


def test_events_during_a_command_follow_its_reply() -> None:
    box: Outbox[str] = Outbox(limit=10)
    box.begin_command()
    box.event("started")
    box.status("s1", key="robot_status")
    box.reply("ok")
    box.event("later")
    assert _drain(box) == ["ok", "started", "s1", "later"]


def test_events_with_no_command_in_flight_go_out_in_order() -> None:
    box: Outbox[str] = Outbox(limit=10)
    box.event("a")
    box.reply("malformed")  # a reply with no command begun (a frame that did not parse)
    box.event("b")
    assert _drain(box) == ["a", "malformed", "b"]


def test_unsent_status_frames_are_coalesced_to_the_newest_per_key() -> None:
    box: Outbox[str] = Outbox(limit=10)
    for i in range(1000):
        box.status(f"s{i}", key="robot_status")
        box.status(f"p{i}", key="pose")
    assert box.pending == 2
    assert box.coalesced == 1998
    assert _drain(box) == ["s999", "p999"]
    box.status("s1000", key="robot_status")
    assert _drain(box) == ["s1000"]


def test_a_reader_that_never_reads_is_closed_with_a_reason_and_stays_bounded() -> None:
    box: Outbox[str] = Outbox(limit=5)
    for i in range(5):
        box.event(f"e{i}")
    assert not box.closed
    for i in range(10_000):
        box.event(f"x{i}")
        box.status(f"s{i}", key="robot_status")
    assert box.closed
    assert box.closed_reason is not None and "not reading" in box.closed_reason
    assert box.pending <= 6


def test_held_events_count_toward_the_bound() -> None:
    box: Outbox[str] = Outbox(limit=3)
    box.begin_command()
    for i in range(4):
        box.event(f"e{i}")
    assert box.closed


def test_get_returns_what_was_queued_then_raises_once_closed() -> None:
    box: Outbox[str] = Outbox(limit=5)
    box.event("last words")
    box.close("bye")

    async def take() -> None:
        assert await box.get() == "last words"
        with pytest.raises(OutboxClosed):
            await box.get()

    asyncio.run(take())


def test_get_waits_for_a_frame() -> None:
    async def run() -> str:
        box: Outbox[str] = Outbox(limit=5)
        getter = asyncio.ensure_future(box.get())
        await asyncio.sleep(0)
        assert not getter.done()
        box.event("e")
        return await getter

    assert asyncio.run(run()) == "e"


def test_limit_must_be_positive() -> None:
    with pytest.raises(ValueError, match="limit"):
        Outbox(limit=0)
