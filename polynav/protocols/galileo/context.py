"""What every Galileo handler shares: the :class:`Context`.

It holds the runtime, the token book, the robot's identity, and the adapter's own bookkeeping
that the runtime has no word for (which Galileo target an attempt was sent to, the status
header's sequence number). Route modules that need state of their own keep it through
:meth:`Context.state`, so adding a module never edits this one.
"""

from __future__ import annotations

import itertools
import logging
import threading
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

from polynav.protocols.galileo.config import GalileoConfig
from polynav.protocols.site_store import site_store
from polynav.runtime.robot_runtime import RobotRuntime
from polynav.store.site_store import SiteStore

if TYPE_CHECKING:
    from polynav.protocols.galileo.auth import TokenBook

log = logging.getLogger(__name__)

T = TypeVar("T")

#: ``targetNumID`` of a goal with no target-point index (galileo-http-a §1.6).
TARGET_WITHOUT_ID = -2


@dataclass(frozen=True, slots=True)
class Target:
    """The Galileo target an attempt was sent to: a (map, path, index), or none (``index`` -2)."""

    index: int
    map_name: str | None = None
    path: str | None = None


@dataclass
class Context:
    """What handlers share.

    Attributes:
        runtime: the robot.
        config: the adapter's configuration.
        tokens: credentials and issued tokens.
        robot_id: the ``id`` of the UDP announcement and ``/system/info``.
        mac: the ``mac`` of the same.
        version: the Galileo API version polynav speaks.
        data_dir: the robot's data directory (everything the adapter writes goes inside).
        targets: the Galileo target of each runtime attempt this adapter started.
    """

    runtime: RobotRuntime
    config: GalileoConfig
    tokens: TokenBook
    robot_id: str
    mac: str
    version: str
    data_dir: Path
    targets: dict[int, Target] = field(default_factory=dict)
    lock: threading.Lock = field(default_factory=threading.Lock)
    _seq: itertools.count[int] = field(default_factory=lambda: itertools.count(1))
    _states: dict[str, Any] = field(default_factory=dict)

    @property
    def store(self) -> SiteStore:
        """The site store (the runtime is typed against the narrower ``SiteData``)."""
        return site_store(self.runtime)

    def next_seq(self) -> int:
        """The next ``header.seq`` of a GalileoStatus."""
        with self.lock:
            return next(self._seq)

    def remember_target(self, attempt_id: int, target: Target) -> None:
        with self.lock:
            self.targets[attempt_id] = target
            # An attempt id is never reused; keep the recent ones only.
            while len(self.targets) > 1024:
                del self.targets[next(iter(self.targets))]

    def target_of(self, attempt_id: int | None) -> Target | None:
        if attempt_id is None:
            return None
        with self.lock:
            return self.targets.get(attempt_id)

    def close(self) -> None:
        """Release what the modules' states hold (event subscriptions): each state with a
        ``close()`` method is closed."""
        with self.lock:
            states = list(self._states.values())
            self._states.clear()
        for value in states:
            close = getattr(value, "close", None)
            if callable(close):
                close()

    def state(self, key: str, factory: Callable[[], T]) -> T:
        """A route module's own state, made by ``factory`` on first use (thread-safe)."""
        with self.lock:
            if key not in self._states:
                self._states[key] = factory()
            value: T = self._states[key]
            return value
