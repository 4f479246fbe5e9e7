"""Navigation attempts as the runtime reports them: runtime-wide ids and runtime events.

The navigator numbers its attempts from 1 and the runtime rebuilds the navigation stack (and so
its navigator) whenever the map or the settings change. Adapters need ids that stay unique for
the runtime's lifetime, so :class:`AttemptBook` adds an offset: the highest id handed out before
the stack was built. It also remembers the last attempt (the status shows it after the goal
ends) and the goal point's name, which the navigator does not know.

:func:`translate` maps one navigator event onto the runtime's events
(:mod:`polynav.runtime.events`).
"""

from __future__ import annotations

import logging

from polynav.nav import events as nav_events
from polynav.nav.attempt import FailureReason, NavigationAttempt
from polynav.runtime import events

log = logging.getLogger(__name__)


def translate(
    event: nav_events.NavigationEvent, attempt_id: int, point: str | None
) -> list[events.RuntimeEvent]:
    """The runtime events one navigator event stands for, in publishing order.

    A retry because the robot was stuck is reported twice, as ``NavigationStuck`` then
    ``NavigationRetry``, since vendor dialects have a distinct "stuck" notification.

    Args:
        event: what the navigator reported.
        attempt_id: the runtime's id of ``event.attempt``.
        point: the goal point's name, for ``NavigationStarted`` (``None`` for a pose goal).

    Returns:
        The runtime events; empty for a navigator event the runtime does not report.
    """
    attempt = event.attempt
    stamp = event.stamp
    distance = float(attempt.distance_travelled)
    out: list[events.RuntimeEvent] = []
    if isinstance(event, nav_events.NavigationStarted):
        out.append(events.NavigationStarted(stamp, attempt_id, attempt.goal, point))
    elif isinstance(event, nav_events.NavigationSucceeded):
        known = attempt.arrival_uncertainty
        out.append(events.NavigationSucceeded(
            stamp, attempt_id, distance,
            position_uncertainty=None if known is None else float(known.position),
            heading_uncertainty=None if known is None else float(known.heading)))
    elif isinstance(event, nav_events.NavigationFailed):
        reason = failure_text(attempt) or "unknown"
        out.append(
            events.NavigationFailed(stamp, attempt_id, reason, distance, attempt.plans > 0)
        )
    elif isinstance(event, nav_events.NavigationCanceled):
        out.append(events.NavigationCanceled(stamp, attempt_id, distance))
    elif isinstance(event, nav_events.NavigationPaused):
        out.append(events.NavigationPaused(stamp, attempt_id))
    elif isinstance(event, nav_events.NavigationResumed):
        out.append(events.NavigationResumed(stamp, attempt_id))
    elif isinstance(event, nav_events.NavigationRetry):
        if event.cause == "stuck":
            out.append(events.NavigationStuck(stamp, attempt_id))
        out.append(events.NavigationRetry(stamp, attempt_id, attempt.retries, event.cause))
    elif isinstance(event, nav_events.PlanFailed):
        out.append(events.PlanningFailed(stamp, attempt_id, event.cause))
    elif isinstance(event, nav_events.NavigationBlocked):
        out.append(events.NavigationBlocked(stamp, attempt_id))
    elif isinstance(event, nav_events.NavigationWaiting):
        out.append(events.NavigationWaiting(stamp, attempt_id, event.cause))
    elif isinstance(event, nav_events.ChargerLeaveRetry):
        out.append(events.ChargerLeaveRetry(stamp, attempt_id, event.retries))
    elif isinstance(event, nav_events.DockingFailed):
        out.append(events.DockingFailed(stamp, attempt_id, event.cause))
    else:
        simple = _SIMPLE.get(type(event))
        if simple is not None:
            out.append(simple(stamp, attempt_id))
    return out


# Navigator events that become a runtime event carrying only the attempt id.
_SIMPLE: dict[type[nav_events.NavigationEvent], type[events.AttemptEvent]] = {
    nav_events.ChargerLeaveStarted: events.ChargerLeaveStarted,
    nav_events.ChargerLeft: events.ChargerLeft,
    nav_events.ChargerLeaveFailed: events.ChargerLeaveFailed,
    nav_events.DockingStarted: events.DockingStarted,
    nav_events.DockingSucceeded: events.DockingSucceeded,
}


def failure_text(attempt: NavigationAttempt) -> str | None:
    """Why ``attempt`` failed, as the status and the ``navigation_failed`` event say it: the
    :class:`~polynav.nav.attempt.FailureReason` value, with what it names where the value
    alone would not tell which (``door closed: door fire_door_west did not open ...``)."""
    if attempt.reason is None:
        return attempt.message or None
    if attempt.reason is FailureReason.DOOR_CLOSED and attempt.message:
        return f"{attempt.reason.value}: {attempt.message}"
    return attempt.reason.value


class AttemptBook:
    """The runtime's record of navigation attempts across navigation stacks.

    Attributes:
        attempt: the last attempt of this navigation session (running or ended), else ``None``.
        attempt_id: its runtime id.
        attempt_point: its goal point's name (``None`` for a pose goal).
        pending_point: the goal point's name while a goal is being started, so that the
            ``NavigationStarted`` the navigator emits from inside ``go_to`` can carry it.
    """

    def __init__(self) -> None:
        self._id_offset = 0
        self._last_id = 0
        self.attempt: NavigationAttempt | None = None
        self.attempt_id: int | None = None
        self.attempt_point: str | None = None
        self.pending_point: str | None = None

    def new_stack(self) -> None:
        """A new navigator counts from 1 again: its ids follow the last one handed out."""
        self._id_offset = self._last_id

    def new_session(self) -> None:
        """Forget the last attempt: it belonged to the previous navigation session."""
        self.attempt = None
        self.attempt_id = None
        self.attempt_point = None

    def reserve_id(self) -> int:
        """A new runtime id for an attempt the navigator does not run itself (a goal on another
        map, made of several navigator goals); later navigator ids come after it."""
        self._last_id += 1
        self._id_offset += 1
        return self._last_id

    def runtime_id(self, navigator_id: int) -> int:
        """The runtime's id of the current navigator's attempt ``navigator_id``."""
        return self._id_offset + navigator_id

    def follow(self, attempt: NavigationAttempt | None) -> None:
        """Keep the latest state of the current attempt (the navigator replaces it each tick)."""
        if attempt is not None and self.runtime_id(attempt.attempt_id) == self.attempt_id:
            self.attempt = attempt

    def record(self, event: nav_events.NavigationEvent) -> list[events.RuntimeEvent]:
        """Take note of a navigator event and return the runtime events to publish for it."""
        attempt = event.attempt
        attempt_id = self.runtime_id(attempt.attempt_id)
        self._last_id = max(self._last_id, attempt_id)
        self.attempt = attempt
        self.attempt_id = attempt_id
        if isinstance(event, nav_events.NavigationStarted):
            self.attempt_point = self.pending_point
        return translate(event, attempt_id, self.pending_point)
