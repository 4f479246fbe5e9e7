"""Counters of what the Galileo wires refused or ignored, for the operator.

Malformed input never crashes a wire; it is dropped, answered with the wire's own error, or
ignored as the spec says. Each such case is also counted here, per robot, so a host that
sends garbage, a PLC that reads a wrong address or a command sent in the wrong state shows in
``GET /api/diagnostics`` of the native API instead of only in a log.
"""

from __future__ import annotations

import threading
from collections import Counter

from polynav.protocols.galileo.context import Context


class Diagnostics:
    """Named counters (``serial.garbage_bytes``, ``native.ignored``, ``modbus.exception_2``, ...),
    thread-safe."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._counts: Counter[str] = Counter()

    def count(self, name: str, n: int = 1) -> None:
        if n:
            with self._lock:
                self._counts[name] += n

    def snapshot(self) -> dict[str, int]:
        with self._lock:
            return dict(sorted(self._counts.items()))


def diagnostics(ctx: Context) -> Diagnostics:
    """The counters of ``ctx``'s robot."""
    return ctx.state("galileo.diagnostics", Diagnostics)
