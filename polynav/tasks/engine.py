"""The task engine: every task of one robot, and the one that runs.

A :class:`Task` is a tree (:mod:`.control`, :mod:`.action`) with a name and a blackboard. The
engine keeps the robot's tasks, runs at most one at a time (starting a task pre-empts the
running one: one robot does one thing at a time, galileo-tasks-bt-ws A-6) and ticks it from the
runtime's control loop. All commands run between ticks (the runtime calls them on its loop);
reads from other threads get :attr:`Task.snapshot`, the tree as JSON values rendered after the
last change, under a lock, so polling a task in a tight loop never waits for the loop.

When the running task ends, however it ends, the settings its ``change_setting_action``s
asked to restore are restored, and the robot is left idle (nothing of the tree runs on).
"""

from __future__ import annotations

import contextlib
import logging
import threading
import uuid
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any

from polynav.errors import Conflict, InvalidRequest, NotFound, PolynavError
from polynav.tasks.blackboard import Blackboard
from polynav.tasks.control import Sequence
from polynav.tasks.node import Node, Run
from polynav.tasks.robot import TaskRobot
from polynav.tasks.states import NodeState

log = logging.getLogger(__name__)

MAX_TASKS = 1000  # ended tasks beyond this are forgotten, oldest first

#: ``on_change(task, node, state)``: a node of a task changed state.
OnChange = Callable[["Task", Node, NodeState], None]


@dataclass(eq=False)
class Task:
    """A tree to run, its blackboard's starting values, and who made it (``owner``: the
    dialect or service, so each lists and controls its own kinds of task)."""

    name: str
    root: Node
    blackboard: dict[str, Any] = field(default_factory=dict)
    owner: str = "native"
    kind: str = "task"
    id: str = field(default_factory=lambda: str(uuid.uuid4()))
    #: Not kept in the site store (Galileo's temporary "auto task", A-13).
    temporary: bool = False
    run: Run | None = None
    snapshot: dict[str, Any] = field(default_factory=dict)
    #: Why the task ended the way it did, when the tree does not say (cancelled by whom).
    note: str = ""
    #: The tree's JSON form as given (:mod:`.tree`), kept so that the task can be stored and
    #: rebuilt after a restart; ``None`` for a tree a dialect built itself (not stored).
    spec: dict[str, Any] | None = None

    def __post_init__(self) -> None:
        Blackboard(self.blackboard)  # the keys and values are checked when made

    @property
    def state(self) -> NodeState:
        return self.root.state

    def describe(self) -> dict[str, Any]:
        return {"id": self.id, "name": self.name, "owner": self.owner, "kind": self.kind,
                "state": self.state.value, "note": self.note, "temporary": self.temporary,
                "blackboard": dict(self.blackboard) if self.run is None
                else self.run.blackboard.values(),
                "tree": self.root.describe()}


class TaskEngine:
    """The robot's tasks; commands and :meth:`tick` between the runtime's ticks."""

    def __init__(self, robot: TaskRobot, *, on_change: OnChange | None = None,
                 on_end: Callable[[Task], None] | None = None) -> None:
        self._robot = robot
        self._on_change = on_change
        self._on_end: list[Callable[[Task], None]] = [] if on_end is None else [on_end]
        self._acting = False
        self._tasks: dict[str, Task] = {}
        self._running: Task | None = None
        # A detour (auto-charge) runs while ``_suspended`` waits paused; ``_resume_after``:
        # whether it was working (a task paused by its user stays paused).
        self._detour: Task | None = None
        self._suspended: Task | None = None
        self._resume_after = False
        self._seen: dict[str, NodeState] = {}
        self._lock = threading.Lock()

    # -- reading (any thread) ----------------------------------------------------------------

    def get(self, task_id: str) -> dict[str, Any]:
        """The task's snapshot.

        Raises:
            NotFound: no such task.
        """
        with self._lock:
            task = self._tasks.get(task_id)
            if task is None:
                raise NotFound("task", task_id)
            return task.snapshot

    def find(self, task_id: str) -> Task:
        """The task itself, for commands between ticks.

        Raises:
            NotFound: no such task.
        """
        with self._lock:
            task = self._tasks.get(task_id)
        if task is None:
            raise NotFound("task", task_id)
        return task

    def tasks(self, owner: str | None = None, kind: str | None = None) -> list[Task]:
        with self._lock:
            return [t for t in self._tasks.values()
                    if (owner is None or t.owner == owner) and (kind is None or t.kind == kind)]

    def snapshots(self, owner: str | None = None, kind: str | None = None
                  ) -> list[dict[str, Any]]:
        return [t.snapshot for t in self.tasks(owner, kind)]

    @property
    def running(self) -> Task | None:
        """The working or paused task."""
        return self._running

    @property
    def acting(self) -> bool:
        """Whether a task is being stepped now: a runtime command made by one of its nodes
        belongs to the task and must not pre-empt it."""
        return self._acting

    def when_ended(self, fn: Callable[[Task], None]) -> None:
        """Call ``fn(task)`` whenever the running task ends, however it ends."""
        self._on_end.append(fn)

    def give_way(self, note: str) -> Task | None:
        """A command from outside the tasks takes the robot: cancel the running task (unless
        the command comes from the task itself); the task cancelled, if any."""
        task = self._running
        if task is None or self._acting:
            return None
        self._drop_suspended(note)
        self._end_running(note)
        return task

    def __iter__(self) -> Iterator[Task]:
        return iter(self.tasks())

    # -- commands (between ticks) -----------------------------------------------------------

    def add(self, task: Task) -> Task:
        """Keep ``task`` (``WAITTING``) without running it."""
        with self._lock:
            if task.id in self._tasks:
                raise Conflict(f"task {task.id} exists")
            self._tasks[task.id] = task
            self._forget_old()
        self._render(task)
        return task

    def replace(self, task_id: str, root: Node | None = None, *, name: str | None = None,
                blackboard: Mapping[str, Any] | None = None) -> Task:
        """Change a task that does not run (its tree, name, blackboard).

        Raises:
            NotFound: no such task.
            Conflict: it runs (pause does not count as stopped).
        """
        task = self.find(task_id)
        if task.state.active:
            raise Conflict(f"task {task_id} is {task.state.value}: stop it first")
        if blackboard is not None:
            Blackboard(blackboard)
            task.blackboard = dict(blackboard)
        if root is not None:
            task.root = root
        if name is not None:
            task.name = name
        self._render(task)
        return task

    def start(self, task_id: str) -> Task:
        """Run the task from its start (a task that ended runs again), pre-empting the one
        that runs.

        Raises:
            NotFound: no such task.
            Conflict: it runs already.
        """
        task = self.find(task_id)
        if task.state.active:
            raise Conflict(f"task {task_id} is {task.state.value} already")
        if self._running is not None:
            self._end_running("cancelled: another task started")
        self._drop_suspended("cancelled: another task started")
        task.root.reset()
        task.note = ""
        task.run = Run(self._robot, Blackboard(task.blackboard), task.id, self._robot.now())
        self._running = task
        self._step(task)
        return task

    def interrupt(self, task: Task) -> Task:
        """Run ``task`` as a detour: the running task is paused until it ends, then resumed
        if it completed (the robot charged), cancelled if not. Nothing runs: ``task`` simply
        runs.

        Raises:
            Conflict: a detour runs already.
        """
        if self._detour is not None:
            raise Conflict(f"a detour ({self._detour.name}) runs already")
        running = self._running
        self.add(task)
        if running is not None and running.run is not None:
            with self._as_task():
                self._resume_after = running.root.pause(running.run)
            self._suspended = running
            self._running = None
            self._render(running)
        self._detour = task
        task.root.reset()
        task.run = Run(self._robot, Blackboard(task.blackboard), task.id, self._robot.now())
        self._running = task
        self._step(task)
        return task

    @property
    def suspended(self) -> Task | None:
        """The task waiting for a detour to end."""
        return self._suspended

    def pause(self, task_id: str, node_id: str | None = None) -> Task:
        """Pause the task (or one node of it, with its subtree).

        Raises:
            NotFound: no such task or node.
            Conflict: that node is not working.
        """
        task = self._switch(task_id, node_id, Node.pause, NodeState.WORKING)
        self._render(task)
        return task

    def resume(self, task_id: str, node_id: str | None = None) -> Task:
        """Resume the paused task (or node).

        Raises:
            NotFound: no such task or node.
            Conflict: that node is not paused.
        """
        task = self._switch(task_id, node_id, Node.resume, NodeState.PAUSED)
        self._step(task)
        return task

    def _switch(self, task_id: str, node_id: str | None, switch: Callable[[Node, Run], bool],
                needed: NodeState) -> Task:
        """Pause or resume a node as the task's own doing; Conflict if it is not ``needed``."""
        task, node = self._node(task_id, node_id)
        with self._as_task():
            done = task.run is not None and switch(node, task.run)
        if not done:
            raise Conflict(f"{'task' if node_id is None else 'node'} "
                           f"{node_id or task_id} is {node.state.value}, not {needed.value}")
        return task

    def cancel(self, task_id: str, node_id: str | None = None) -> Task:
        """Cancel the task (or one node of it: its parent takes that as a failed child).
        A task that ended is left as it is.

        Raises:
            NotFound: no such task or node.
        """
        task, node = self._node(task_id, node_id)
        if node is task.root:
            if task is self._running:
                self._end_running("cancelled")
            elif task is self._suspended:
                self._drop_suspended("cancelled")
            elif not task.state.final:
                node.cancel(self._run_of(task))
                self._render(task)
            return task
        with self._as_task():
            cancelled = node.cancel(self._run_of(task))
        if cancelled and task is self._running:
            self._step(task)
        return task

    def cancel_all(self) -> list[Task]:
        """Cancel the running task; the tasks cancelled."""
        task = self._running
        if task is None:
            return []
        self._end_running("cancelled")
        return [task]

    def set_loop(self, task_id: str, loop: bool, node_id: str | None = None) -> Task:
        """Set ``loop_flag`` of the task's root (or of a sequence node).

        Raises:
            NotFound: no such task or node.
            InvalidRequest: the node is not a sequence.
        """
        task, node = self._node(task_id, node_id)
        if not isinstance(node, Sequence) or node.kind != "sequence":
            raise InvalidRequest("loop_flag", f"{node.kind} nodes do not loop by flag")
        node.loop_flag = loop
        self._render(task)
        return task

    def delete(self, task_id: str) -> None:
        """Forget a task that does not run.

        Raises:
            NotFound: no such task.
            Conflict: it runs.
        """
        task = self.find(task_id)
        if task.state.active:
            raise Conflict(f"task {task_id} is {task.state.value}: stop it first")
        with self._lock:
            del self._tasks[task_id]

    def trigger(self) -> int:
        """Release every waiting ``wait_req_action`` of the running task; how many waited."""
        task = self._running
        if task is None or task.run is None:
            return 0
        waiting = sum(1 for n in task.root.walk()
                      if getattr(n, "type", None) == "wait_req_action"
                      and n.state is NodeState.WORKING)
        task.run.triggers = waiting
        self._step(task)
        task.run.triggers = 0
        return waiting

    # -- the loop --------------------------------------------------------------------------

    def tick(self, now: float) -> None:
        """Advance the running task (from the runtime's control loop)."""
        task = self._running
        if task is None or task.state is NodeState.PAUSED:
            return
        self._step(task)

    def _step(self, task: Task) -> None:
        run = task.run
        assert run is not None
        run.now = self._robot.now()
        with self._as_task():
            try:
                if task.root.state is not NodeState.PAUSED:
                    task.root.tick(run)
            except PolynavError as exc:  # a node's own refusal ends the tree, never the loop
                log.error("task %s: %s", task.id, exc)
                task.root.end(run, NodeState.ERROR, str(exc))
        if run.taken is not None and task.state.active:
            self._end_running(run.taken)
            return
        if task.state.final and task is self._running:
            self._finish(task)
        self._render(task)

    def _end_running(self, note: str) -> None:
        task = self._running
        assert task is not None and task.run is not None
        with self._as_task():
            task.root.cancel(task.run)
        task.note = note
        self._finish(task)
        self._render(task)

    def _finish(self, task: Task) -> None:
        """The running task ended: settle it, forget it as running, end a detour."""
        self._running = None
        self._settle(task)
        if task is self._detour:
            self._detour = None
            self._after_detour(task)

    def _after_detour(self, detour: Task) -> None:
        task = self._suspended
        if task is None or task.run is None:
            return
        self._suspended = None
        self._running = task
        if detour.state is not NodeState.COMPLETE:
            self._end_running(f"cancelled: {detour.name} ended {detour.state.value}"
                              f"{': ' + detour.note if detour.note else ''}")
            return
        if self._resume_after:
            with self._as_task():
                task.root.resume(task.run)
        self._step(task)

    def _drop_suspended(self, note: str) -> None:
        task = self._suspended
        if task is None or task.run is None:
            return
        self._suspended = None
        with self._as_task():
            task.root.cancel(task.run)
        task.note = note
        self._settle(task)
        self._render(task)

    def _settle(self, task: Task) -> None:
        """A task ended: restore the settings it changed, tell who listens."""
        run = task.run
        assert run is not None
        for settings in reversed(run.restore):
            try:
                self._robot.change_settings(settings)
            except PolynavError as exc:
                log.error("task %s: settings not restored: %s", task.id, exc)
        run.restore.clear()
        for fn in self._on_end:
            fn(task)

    @contextlib.contextmanager
    def _as_task(self) -> Iterator[None]:
        """What runs inside is the task's own doing (see :attr:`acting`)."""
        outer = self._acting
        self._acting = True
        try:
            yield
        finally:
            self._acting = outer

    def _run_of(self, task: Task) -> Run:
        return task.run or Run(self._robot, Blackboard(task.blackboard), task.id,
                               self._robot.now())

    def _node(self, task_id: str, node_id: str | None) -> tuple[Task, Node]:
        task = self.find(task_id)
        if node_id is None:
            return task, task.root
        node = task.root.find(node_id)
        if node is None:
            raise NotFound("node", node_id)
        return task, node

    def refresh(self, task: Task) -> None:
        """Render ``task``'s snapshot again after a change outside the tree (its note)."""
        self._render(task)

    def _render(self, task: Task) -> None:
        snapshot = task.describe()
        with self._lock:
            task.snapshot = snapshot
        if self._on_change is None:
            return
        for node in task.root.walk():
            if self._seen.get(node.id) is not node.state:
                self._seen[node.id] = node.state
                self._on_change(task, node, node.state)
        if len(self._seen) > 100_000:
            self._seen.clear()

    def _forget_old(self) -> None:
        while len(self._tasks) > MAX_TASKS:
            oldest = next((k for k, t in self._tasks.items() if t.state.final), None)
            if oldest is None:
                return
            del self._tasks[oldest]
