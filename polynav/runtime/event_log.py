"""The robot's event log: the latest runtime events as text lines, for "system log" queries.

It subscribes to the runtime's bus when the runtime is built, so the log covers the robot's
life from power-on; the subscription is bounded (:data:`LOG_LINES`), so an unread log costs a
few hundred events, never more. Lines read ``[<stamp>] <kind> <JSON of the other fields>``.
"""

from __future__ import annotations

import json
import threading
from collections import deque

from polynav.runtime.event_bus import EventBus

LOG_LINES = 500


class EventLog:
    """The last :data:`LOG_LINES` events of ``bus``, oldest first."""

    def __init__(self, bus: EventBus) -> None:
        self._subscription = bus.subscribe(maxlen=LOG_LINES)
        self._lines: deque[str] = deque(maxlen=LOG_LINES)
        self._lock = threading.Lock()

    def text(self) -> str:
        with self._lock:
            for event in self._subscription.get_nowait():
                fields = {k: v for k, v in event.to_dict().items() if k not in ("stamp", "kind")}
                self._lines.append(f"[{event.stamp:.3f}] {event.kind} "
                                   + json.dumps(fields, default=str, ensure_ascii=False))
            return "\n".join(self._lines)
