from __future__ import annotations

import asyncio
import threading

import pytest

from polynav.errors import InvalidRequest
from polynav.runtime.event_bus import EventBus
from polynav.runtime.events import ChargeChanged, LowBattery


def test_subscribers_receive_events_in_publish_order() -> None:
    bus = EventBus()
    a, b = bus.subscribe(), bus.subscribe()
    for i in range(5):
        bus.publish(LowBattery(float(i), 10.0 - i))
    assert [e.stamp for e in a.get_nowait()] == [0.0, 1.0, 2.0, 3.0, 4.0]
    assert [e.stamp for e in b.get_nowait()] == [0.0, 1.0, 2.0, 3.0, 4.0]
    assert a.get_nowait() == []


def test_a_subscriber_only_sees_events_published_after_it_subscribed() -> None:
    bus = EventBus()
    bus.publish(ChargeChanged(0.0, True))
    sub = bus.subscribe()
    bus.publish(ChargeChanged(1.0, False))
    assert sub.get_nowait() == [ChargeChanged(1.0, False)]


def test_slow_subscriber_overflow_drops_the_oldest_and_counts_them() -> None:
    bus = EventBus()
    slow = bus.subscribe(maxlen=3)
    fast = bus.subscribe(maxlen=100)
    for i in range(10):
        bus.publish(LowBattery(float(i), 5.0))
    assert [e.stamp for e in slow.get_nowait()] == [7.0, 8.0, 9.0]
    assert slow.dropped == 7
    assert len(fast.get_nowait()) == 10
    assert fast.dropped == 0


def test_publish_never_waits_for_a_subscriber_that_never_reads() -> None:
    bus = EventBus()
    stuck = bus.subscribe(maxlen=10)
    done = threading.Event()

    def publisher() -> None:
        for i in range(20_000):
            bus.publish(LowBattery(float(i), 1.0))
        done.set()

    thread = threading.Thread(target=publisher)
    thread.start()
    thread.join(timeout=60.0)
    assert done.is_set()
    assert stuck.dropped == 19_990
    assert [e.stamp for e in stuck.get_nowait()][0] == 19_990.0


def test_wait_returns_events_published_from_another_thread() -> None:
    bus = EventBus()
    sub = bus.subscribe()
    timer = threading.Timer(0.01, lambda: bus.publish(ChargeChanged(4.0, True)))
    timer.start()
    got = sub.wait(timeout=30.0)
    timer.join()
    assert got == [ChargeChanged(4.0, True)]


def test_unsubscribe_stops_delivery_and_wakes_a_waiter() -> None:
    bus = EventBus()
    sub = bus.subscribe()
    result: list[object] = []
    waiter = threading.Thread(target=lambda: result.append(sub.wait(timeout=30.0)))
    waiter.start()
    bus.unsubscribe(sub)
    waiter.join(timeout=30.0)
    assert result == [[]]
    bus.publish(ChargeChanged(1.0, True))
    assert sub.get_nowait() == []
    assert sub.closed
    assert bus.subscriber_count == 0


def test_async_get_is_woken_by_a_publish_from_another_thread() -> None:
    bus = EventBus()
    sub = bus.subscribe()

    async def main() -> list[object]:
        loop = asyncio.get_running_loop()
        loop.call_later(0.01, lambda: threading.Thread(
            target=bus.publish, args=(ChargeChanged(2.0, False),)).start())
        return list(await asyncio.wait_for(sub.get(), timeout=30.0))

    assert asyncio.run(main()) == [ChargeChanged(2.0, False)]


def test_subscribe_refuses_a_queue_of_no_events() -> None:
    with pytest.raises(InvalidRequest) as info:
        EventBus().subscribe(maxlen=0)
    assert info.value.field == "maxlen"
