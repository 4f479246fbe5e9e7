"""What runs on the runtime's loop besides control: timers the services set, and listeners
told after every physics step.

Services schedule follow-ups on the runtime's clock (a power-off 10 s after its notice); servers
stream sensors at their own rates on the same clock (a scan at 15 Hz of simulated time). Both
run between steps on the loop, and a fault in one never stops the robot.
"""

from __future__ import annotations

import heapq
import itertools
import logging
from collections.abc import Callable
from typing import Protocol

from polynav.errors import PolynavError

log = logging.getLogger(__name__)

_EPS = 1e-9


class StepHooks:
    """Timers by due time, and step listeners in the order they came."""

    def __init__(self) -> None:
        self._timers: list[tuple[float, int, Callable[[], None]]] = []
        self._seq = itertools.count()
        self._listeners: list[Callable[[float], None]] = []

    def schedule(self, due: float, fn: Callable[[], None]) -> None:
        """Run ``fn`` at the first step at or after ``due``."""
        heapq.heappush(self._timers, (due, next(self._seq), fn))

    def run_due(self, now: float) -> None:
        """Run the timers due by ``now``; one that fails is logged."""
        while self._timers and self._timers[0][0] <= now + _EPS:
            _, _, fn = heapq.heappop(self._timers)
            try:
                fn()
            except PolynavError:  # a follow-up that cannot happen must not stop the robot
                log.error("a scheduled step failed", exc_info=True)

    def add_listener(self, listener: Callable[[float], None]) -> Callable[[], None]:
        """Call ``listener(now)`` after every step; returns the function that removes it."""
        self._listeners.append(listener)

        def remove() -> None:
            if listener in self._listeners:
                self._listeners.remove(listener)

        return remove

    def stepped(self, now: float) -> None:
        """Tell the listeners a step happened; one that fails is logged."""
        for listener in tuple(self._listeners):
            try:
                listener(now)
            except Exception:  # a server's fault must not stop the robot
                log.exception("a step listener failed")


class _Clocked(Protocol):
    def now(self) -> float: ...

    def add_step_listener(self, listener: Callable[[float], None]) -> Callable[[], None]: ...


def every(runtime: _Clocked, period: float, fn: Callable[[], None]) -> Callable[[], None]:
    """Call ``fn`` every ``period`` seconds of the runtime's clock, at the first step on or
    after each due time (the first at once); after a jump of the clock one call catches up,
    not a burst. Returns the function that stops it."""
    due = runtime.now()

    def on_step(now: float) -> None:
        nonlocal due
        if now < due - _EPS:
            return
        due = max(due + period, now)
        fn()

    return runtime.add_step_listener(on_step)
