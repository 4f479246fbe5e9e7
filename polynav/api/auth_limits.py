"""Slowing down password guessing: consecutive failed logins per user and per client address.

Each key (``user:<name>``, ``addr:<host>``) counts its failed logins in a row. The first
:attr:`LoginLimiter.free` failures cost nothing; after that, the next attempt is allowed only
``base * 2 ** (failures - free)`` seconds (capped at ``cap``) after the last failure, and an
attempt before then is refused at once with the wait (HTTP 429 with ``Retry-After``), without
checking the password, so nothing sleeps and the event loop is never blocked. A success clears
both keys.

An attempt counts as a failure from the moment it starts and is forgiven only if it succeeds,
so parallel guesses cannot all slip in while the first ones are still being hashed.

Per user, a stranger can delay a user's own login by failing on purpose; the cap bounds that
delay (5 minutes by default), and the per-address key still slows the stranger down first.
The table is bounded: past ``max_keys`` the least recently used keys are forgotten.
"""

from __future__ import annotations

import logging
import threading
import time
from collections import OrderedDict
from collections.abc import Callable, Sequence
from dataclasses import dataclass

log = logging.getLogger(__name__)


@dataclass(slots=True)
class _Failures:
    count: int
    last: float  # [s] on the limiter's clock


class LoginLimiter:
    """Consecutive failed logins per key, and the wait they impose.

    Args:
        free: failures in a row allowed without a wait.
        base: the first wait [s], doubled with each further failure.
        cap: the longest wait [s].
        max_keys: keys remembered at most.
        clock: monotonic seconds; tests pass a fake one.
    """

    def __init__(
        self, *, free: int = 5, base: float = 1.0, cap: float = 300.0, max_keys: int = 10_000,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        if free < 0 or base <= 0.0 or cap < base or max_keys < 1:
            raise ValueError("free >= 0, 0 < base <= cap and max_keys >= 1")
        self.free = free
        self.base = base
        self.cap = cap
        self.max_keys = max_keys
        self.clock = clock
        self._failures: OrderedDict[str, _Failures] = OrderedDict()
        self._lock = threading.Lock()

    def _wait(self, key: str, now: float) -> float:
        entry = self._failures.get(key)
        if entry is None or entry.count < self.free:
            return 0.0
        delay = min(self.cap, self.base * 2.0 ** (entry.count - self.free))
        return max(0.0, entry.last + delay - now)

    def attempt(self, keys: Sequence[str]) -> float:
        """Start a login attempt on ``keys``.

        Returns:
            0.0 if the attempt may go on (it now counts as a failure until :meth:`succeeded`),
            else the seconds to wait before the next one (nothing is counted).
        """
        with self._lock:
            now = self.clock()
            wait = max((self._wait(key, now) for key in keys), default=0.0)
            if wait > 0.0:
                return wait
            for key in keys:
                entry = self._failures.pop(key, None) or _Failures(0, now)
                entry.count += 1
                entry.last = now
                self._failures[key] = entry  # the most recently used go last
            while len(self._failures) > self.max_keys:
                self._failures.popitem(last=False)
            return 0.0

    def succeeded(self, keys: Sequence[str]) -> None:
        """The attempt on ``keys`` succeeded: forget their failures."""
        with self._lock:
            for key in keys:
                self._failures.pop(key, None)

    def failures(self, key: str) -> int:
        """Failed attempts in a row on ``key`` (for tests and diagnostics)."""
        with self._lock:
            entry = self._failures.get(key)
            return 0 if entry is None else entry.count
