"""Runtime events to Yunji notifications (§3.10), sent to every connected client.

Only the codes whose trigger polynav produces today are in :data:`NOTIFICATIONS`; the rest of the
spec's table (cruise, charging-pile docking, lifts, gates, trapped/planning, power) comes with the
features behind them. ``data`` carries ``target`` (the move's marker, ``""`` for a location,
§A-N2) and, when a move ends, ``distance`` travelled [m] (§3.10.3).
"""

from __future__ import annotations

import logging
from collections.abc import Callable

from polynav.protocols.yunji.messages import Notification
from polynav.runtime import events

log = logging.getLogger(__name__)

# code -> (level, description), as the spec's table has them.
NOTIFICATIONS: dict[str, tuple[str, str]] = {
    "01001": ("info", "The move task is started."),
    "01002": ("info", "The move task is finished."),
    "01003": ("warning", "The move task is failed."),
    "01004": ("info", "The move task is canceled."),
    "02003": ("info", "Estop on."),
    "02004": ("info", "Estop off."),
}

_MOVE_END: dict[type[events.RuntimeEvent], str] = {
    events.NavigationSucceeded: "01002",
    events.NavigationFailed: "01003",
    events.NavigationCanceled: "01004",
}


def notification(code: str, data: dict[str, object] | None = None) -> Notification:
    level, description = NOTIFICATIONS[code]
    return Notification(code, level, description, data if data is not None else {})


class NotificationMapper:
    """Turns runtime events into notifications; keeps what it needs across events (the target
    of each attempt, the last combined e-stop state).

    Args:
        target_of: the marker name the adapter recorded for an attempt id, if any (moves sent
            as a pose built from a marker carry no point name in their events).
        estop_active: the combined e-stop state when mapping starts.
    """

    def __init__(self, target_of: Callable[[int], str | None], estop_active: bool) -> None:
        self._target_of = target_of
        self._targets: dict[int, str] = {}
        self._estop = estop_active

    def map(self, event: events.RuntimeEvent) -> list[Notification]:
        if isinstance(event, events.NavigationStarted):
            target = event.point or self._target_of(event.attempt_id) or ""
            self._targets[event.attempt_id] = target
            return [notification("01001", {"target": target})]
        if isinstance(
            event,
            (events.NavigationSucceeded, events.NavigationFailed, events.NavigationCanceled),
        ):
            code = _MOVE_END[type(event)]
            target = self._targets.pop(event.attempt_id, "") or (
                self._target_of(event.attempt_id) or ""
            )
            data: dict[str, object] = {"target": target, "distance": float(event.distance)}
            return [notification(code, data)]
        if isinstance(event, events.EStopChanged) and event.active != self._estop:
            self._estop = event.active
            return [notification("02003" if event.active else "02004")]
        return []
