"""Galileo task objects created by the navigation endpoints, run on the runtime's clock, and
``GET /api/v1/task`` to read them.

A task is an ordered list of actions (:mod:`polynav.protocols.galileo.actions`), run one after
the other (galileo-tasks-bt-ws §3): the task is ``WORKING`` while they run, ``COMPLETE`` when
the last one completes (a ``loop_flag`` task starts over and counts ``loop_count``), ``ERROR``
when one errs, ``CANCELLED`` when stopped, or when its navigation attempt is canceled by
anyone (another task, another dialect). The robot does one thing at a time, so starting a task
cancels the task that was running (A-6: pre-empt).

The book advances on the runtime's clock: a timer (:meth:`RobotRuntime.schedule`) polls the
running task every :data:`POLL_PERIOD` simulated seconds, between ticks. Reading a task
(``GET /task?id=``, polled in a tight loop by real scripts) only copies what the last poll
left, under a lock: no runtime call.
"""

from __future__ import annotations

import logging
import threading
import uuid
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from polynav.errors import Conflict, NotFound, PolynavError
from polynav.protocols.galileo import system_tasks
from polynav.protocols.galileo.actions import FINAL, Action, Outcomes
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.endpoint import Reply, RouteList
from polynav.protocols.galileo.messages import TaskState
from polynav.protocols.galileo.params import Params
from polynav.runtime.robot_runtime import RobotRuntime

log = logging.getLogger(__name__)

ROUTES = RouteList()

POLL_PERIOD = 0.1  # [s] of the runtime's clock between polls of the running task
MAX_TASKS = 1000  # finished tasks beyond this are forgotten, oldest first


@dataclass
class Task:
    """A task: its actions and where it is."""

    name: str
    actions: list[Action]
    loop_flag: bool = False
    kind: str = "navigation"
    id: str = field(default_factory=lambda: str(uuid.uuid4()))
    state: TaskState = TaskState.WAITTING
    index: int = 0
    loop_count: int = 0
    snapshot: dict[str, Any] = field(default_factory=dict)

    @property
    def current(self) -> Action | None:
        if self.state in (TaskState.WORKING, TaskState.PAUSED) and self.index < len(
            self.actions
        ):
            return self.actions[self.index]
        return None

    def render(self, runtime: RobotRuntime) -> dict[str, Any]:
        subs = [a.to_dict(runtime) for a in self.actions]
        current: dict[str, Any] | None = None
        if self.state is not TaskState.WAITTING and self.index < len(subs):
            current = subs[self.index]
        done = sum(1 for a in self.actions if a.state is TaskState.COMPLETE)
        progress = round(done / len(self.actions), 3) if self.actions else 0
        return {"id": self.id, "name": self.name, "loop_flag": self.loop_flag,
                "state": self.state.value, "sub_tasks": subs, "progress": progress,
                "current_task": current, "loop_count": self.loop_count}


class TaskBook:
    """Every task this adapter created, and the runner of the one that is running."""

    def __init__(self, runtime: RobotRuntime) -> None:
        self._runtime = runtime
        self._tasks: dict[str, Task] = {}
        self._lock = threading.Lock()
        self._outcomes = Outcomes(runtime)
        self._polling = False

    def close(self) -> None:
        self._outcomes.close()

    # -- reading (any thread, cheap) ------------------------------------------------------------

    def get(self, task_id: str) -> dict[str, Any]:
        """The task's last rendered state.

        Raises:
            NotFound: no such task.
        """
        with self._lock:
            task = self._tasks.get(task_id)
            if task is None:
                raise NotFound("task", task_id)
            return task.snapshot

    def all(self) -> list[dict[str, Any]]:
        with self._lock:
            return [t.snapshot for t in self._tasks.values()]

    def running(self, kind: str | None = None) -> Task | None:
        """The working or paused task (of ``kind``), if any."""
        with self._lock:  # the running task is nearly always the newest: no copy, no full scan
            for task in reversed(self._tasks.values()):
                if task.state in (TaskState.WORKING, TaskState.PAUSED) and (
                    kind is None or task.kind == kind
                ):
                    return task
        return None

    def last(self, kind: str) -> Task | None:
        with self._lock:
            for task in reversed(self._tasks.values()):
                if task.kind == kind:
                    return task
        return None

    # -- commands (handler threads) ---------------------------------------------------------------

    def run(self, name: str, actions: Sequence[Action], *, loop_flag: bool = False,
            kind: str = "navigation", raise_errors: bool = True, preempt: bool = True
            ) -> dict[str, Any]:
        """Create a task and start it, cancelling the running one; its rendered state.

        Raises:
            Conflict: the first action could not start (the task is kept, in ``ERROR``), unless
                ``raise_errors`` is off: the task in ``ERROR`` is returned then.

        ``preempt`` off leaves the running task alone (a task that does not move the robot).
        """
        task = Task(name, list(actions), loop_flag=loop_flag, kind=kind)
        if not task.actions:
            raise Conflict("a task needs at least one action")

        def begin() -> None:
            if preempt:
                self._cancel_running()
            with self._lock:
                self._tasks[task.id] = task
                self._forget_old()
            task.state = TaskState.WORKING
            self._start_action(task)
            self._render(task)
            self._ensure_polling()

        self._runtime.run_between_ticks(begin)
        if task.state is TaskState.ERROR and raise_errors:
            current = task.actions[task.index]
            raise Conflict(current.result or "the task could not start")
        return task.snapshot

    def build(self, name: str, actions: Sequence[Action], *, kind: str) -> dict[str, Any]:
        """Create a task without running it (``WAITTING``)."""
        task = Task(name, list(actions), kind=kind)
        with self._lock:
            self._tasks[task.id] = task
            self._forget_old()
        self._render(task)
        return task.snapshot

    def cancel(self, task_id: str | None = None, *, kind: str | None = None
               ) -> dict[str, Any] | None:
        """Cancel a task (by id, else the running one of ``kind``); its state, ``None`` when
        there was none."""

        def stop() -> Task | None:
            if task_id is not None:
                with self._lock:
                    task = self._tasks.get(task_id)
                if task is None:
                    raise NotFound("task", task_id)
            else:
                task = self.running(kind)
            if task is None:
                return None
            self._cancel(task)
            return task

        task = self._runtime.run_between_ticks(stop)
        return None if task is None else task.snapshot

    # -- on the loop -------------------------------------------------------------------------------

    def _cancel_running(self) -> None:
        task = self.running()
        if task is not None:
            self._cancel(task)

    def _cancel(self, task: Task) -> None:
        if task.state in FINAL:
            return
        current = task.current
        if current is not None and current.state in (TaskState.WORKING, TaskState.PAUSED):
            try:
                current.cancel(self._runtime)
            except PolynavError as exc:
                log.info("galileo: task %s: cancel: %s", task.id, exc)
        for action in task.actions[task.index:]:
            if action.state not in FINAL:
                action.state = TaskState.CANCELLED
        task.state = TaskState.CANCELLED
        self._render(task)

    def _start_action(self, task: Task) -> None:
        action = task.actions[task.index]
        action.state = TaskState.WORKING
        try:
            action.start(self._runtime)
        except PolynavError as exc:
            log.info("galileo: task %s: %s failed to start: %s", task.id, action.type, exc)
            action.state = TaskState.ERROR
            action.result = str(exc)
            task.state = TaskState.ERROR

    def _ensure_polling(self) -> None:
        if not self._polling:
            self._polling = True
            self._runtime.schedule(POLL_PERIOD, self._poll)

    def _poll(self) -> None:
        task = self.running()
        if task is None:
            self._polling = False
            return
        if task.state is TaskState.WORKING:
            self._advance(task)
        self._render(task)
        self._runtime.schedule(POLL_PERIOD, self._poll)

    def _advance(self, task: Task) -> None:
        action = task.actions[task.index]
        ended = action.poll(self._runtime, self._outcomes)
        if ended is None:
            return
        action.state = ended
        if ended is TaskState.CANCELLED:
            self._cancel(task)
            return
        if ended is TaskState.ERROR:
            task.state = TaskState.ERROR
            return
        task.index += 1
        if task.index >= len(task.actions):
            if not task.loop_flag:
                task.state = TaskState.COMPLETE
                return
            task.loop_count += 1
            task.index = 0
            for a in task.actions:
                a.reset()
        self._start_action(task)

    def _render(self, task: Task) -> None:
        snapshot = task.render(self._runtime)
        with self._lock:
            task.snapshot = snapshot

    def _forget_old(self) -> None:
        while len(self._tasks) > MAX_TASKS:
            oldest = next(iter(self._tasks))
            if self._tasks[oldest].state not in FINAL:
                break
            del self._tasks[oldest]


def book(ctx: Context) -> TaskBook:
    """The context's task book."""
    return ctx.state("tasks", lambda: TaskBook(ctx.runtime))


@ROUTES.get("/task", inline=True)
def get_task(ctx: Context, params: Params) -> Reply:
    """``GET /api/v1/task[?id=]`` (galileo-tasks-bt-ws §4.1) for the tasks this adapter made:
    one task object, or all of them in an array."""
    tasks = book(ctx)
    task_id = params.text("id", None)
    if task_id is None:
        return tasks.all()
    try:
        return tasks.get(task_id)
    except NotFound:
        device = system_tasks.device_task(ctx, task_id)  # a slide, jacking or video task
        if device is None:
            raise
        return device
