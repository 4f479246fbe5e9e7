"""The runtime's patrols: a patrol's legs started as navigation goals, one after the other.

:class:`PatrolRunner` keeps the current (or last) patrol of the runtime and, each control tick
after the navigator ran, starts the next leg as soon as the current one ended; it publishes the
patrol's events around the legs' own. It drives navigation only through the functions the
runtime gives it (start a goal to a point, cancel the goal, publish), so it runs between ticks
like every runtime command.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import replace

from polynav.errors import PolynavError
from polynav.nav.attempt import GoalOptions, NavigationAttempt, NavigationState
from polynav.runtime import events
from polynav.tasks.patrol import Patrol, PatrolPlan, PatrolState

log = logging.getLogger(__name__)

StartLeg = Callable[[str, GoalOptions], int]


class PatrolRunner:
    """Runs one patrol at a time.

    Args:
        start_leg: start a goal to a point of the current map with the given options.
        cancel_goal: cancel the running goal (``False`` if none ran).
        publish: publish a runtime event.
        now: the runtime's clock.
    """

    def __init__(
        self,
        start_leg: StartLeg,
        cancel_goal: Callable[[], bool],
        publish: Callable[[events.RuntimeEvent], None],
        now: Callable[[], float],
    ) -> None:
        self._start_leg = start_leg
        self._cancel_goal = cancel_goal
        self._publish = publish
        self._now = now
        self._seq = 0
        self._options = GoalOptions()
        self.patrol: Patrol | None = None

    @property
    def state(self) -> str | None:
        """The current or last patrol's state, ``None`` when the last task was a single goal."""
        return None if self.patrol is None else self.patrol.state.value

    @property
    def running(self) -> bool:
        return self.patrol is not None and self.patrol.running

    def start(self, plan: PatrolPlan, options: GoalOptions | None) -> int:
        """End a running patrol, start ``plan``'s first leg; returns the patrol id."""
        self.end()
        self._seq += 1
        patrol = Patrol(self._seq, plan)
        self.patrol = patrol
        self._options = replace(options or GoalOptions(), pass_tolerance=plan.tolerance)
        self._event(events.PatrolStarted, patrol)
        self._start_leg(patrol.point, self._options)
        return patrol.patrol_id

    def forget(self) -> None:
        """A single goal replaces the patrol as the last task (after :meth:`end`)."""
        self.patrol = None

    def end(self) -> bool:
        """Cancel a running patrol and its leg; ``False`` if none ran."""
        patrol = self.patrol
        if patrol is None or not patrol.cancel():
            return False
        self._cancel_goal()
        self._event(events.PatrolCanceled, patrol)
        return True

    def follow(self, attempt: NavigationAttempt | None) -> None:
        """After a control tick: start the next leg when the current one ended."""
        patrol = self.patrol
        if patrol is None or not patrol.running or attempt is None:
            return
        if not attempt.state.finished:
            return
        if attempt.state is NavigationState.CANCELED:
            self.end()
            return
        point = patrol.leg_ended(attempt.state is NavigationState.SUCCEEDED)
        if point is not None:
            try:
                self._start_leg(point, self._options)
                return
            except PolynavError as exc:  # the point was deleted meanwhile: the patrol ends
                log.warning("patrol %d: cannot start the leg to %r: %s",
                            patrol.patrol_id, point, exc)
                patrol.state = PatrolState.FAILED
        finished = patrol.state is PatrolState.SUCCEEDED
        self._event(events.PatrolFinished if finished else events.PatrolFailed, patrol)

    def _event(self, cls: type[events.PatrolEvent], patrol: Patrol) -> None:
        plan = patrol.plan
        self._publish(cls(self._now(), patrol.patrol_id, plan.points, plan.count, plan.tolerance))
