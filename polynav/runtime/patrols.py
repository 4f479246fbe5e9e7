"""The runtime's patrols: a patrol is a task on the task engine; this module names it.

:class:`Patrols` makes each patrol's tree (:func:`polynav.tasks.patrol.patrol_tree`), runs it
as the robot's task and reports it in the patrol's own words: a patrol id, ``patrol_started``
then ``patrol_finished``, ``patrol_failed`` (the last leg failed) or ``patrol_canceled`` as the
task ends (the engine tells at once, so the patrol's end comes before whatever ended it starts),
and the status's ``patrol_state``. The legs' navigation events are the goals' own.
"""

from __future__ import annotations

from collections.abc import Callable

from polynav.nav.attempt import GoalOptions
from polynav.runtime import events
from polynav.tasks.engine import Task, TaskEngine
from polynav.tasks.patrol import PatrolPlan, PatrolState, patrol_tree

PATROL = "patrol"  # the task kind


class Patrols:
    """The robot's current or last patrol, run on ``engine``."""

    def __init__(self, engine: TaskEngine, publish: Callable[[events.RuntimeEvent], None],
                 now: Callable[[], float]) -> None:
        self._engine = engine
        self._publish = publish
        self._now = now
        self._seq = 0
        self._ids: dict[str, tuple[int, PatrolPlan]] = {}
        self._last: Task | None = None
        engine.when_ended(self._ended)

    @property
    def state(self) -> str | None:
        """The current or last patrol's state; ``None`` when the last task was not one."""
        if self._last is None:
            return None
        return PatrolState.of(self._last.state).value

    def start(self, plan: PatrolPlan, options: GoalOptions | None) -> int:
        """Run a patrol of ``plan`` (pre-empting the running task); its patrol id."""
        self._seq += 1
        task = Task(f"patrol {self._seq}", patrol_tree(plan, options), owner="runtime",
                    kind=PATROL, temporary=True)
        self._ids[task.id] = (self._seq, plan)
        self._engine.add(task)
        self._last = task
        self._event(events.PatrolStarted, task)
        self._engine.start(task.id)
        return self._seq

    def forget(self) -> None:
        """Something else is the last task now."""
        self._last = None

    def _ended(self, task: Task) -> None:
        if task.id not in self._ids:
            last = self._last
            if last is not None and last not in (self._engine.running, self._engine.suspended):
                self._last = None  # another task ran after the patrol
            return
        state = PatrolState.of(task.state)
        kind = {PatrolState.SUCCEEDED: events.PatrolFinished,
                PatrolState.FAILED: events.PatrolFailed}.get(state, events.PatrolCanceled)
        self._event(kind, task)
        self._ids.pop(task.id)
        self._engine.delete(task.id)

    def _event(self, cls: type[events.PatrolEvent], task: Task) -> None:
        patrol_id, plan = self._ids[task.id]
        self._publish(cls(self._now(), patrol_id, plan.points, plan.count, plan.tolerance))
