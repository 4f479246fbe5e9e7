"""The runtime's task commands: the task engine's commands between ticks, for every adapter.

Dialects create, read and control tasks only here (the engine itself is
:mod:`polynav.tasks.engine`); every command runs between ticks like the runtime's others, and
reads return the engine's snapshots without waiting for the loop. Each node's state change is
published as a :class:`~polynav.runtime.events.TaskChanged` event.

Persistence (DESIGN §6): a task that is not temporary and was made from the tree's JSON form is
kept in the site store, its form as given, when it is made, replaced or deleted, and its root's
state on every change of it. When the runtime starts (:meth:`TaskCommands.load`) the stored
tasks come back ``WAITTING``, except one that was ``WORKING`` or ``PAUSED``: the robot stopped
in the middle of it, and running it again unasked could drive a robot somebody has moved since,
so it is reported ``CANCELLED`` with the note :data:`INTERRUPTED` (and stored so), never re-run
silently. A store that fails while the loop runs is logged, never raised into the loop: the task
goes on, only its record is behind. Schedules: :mod:`~polynav.runtime.task_schedules`.
"""

from __future__ import annotations

import copy
import logging
from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING, Any, TypeVar

from polynav.errors import Conflict, PolynavError, StorageError
from polynav.runtime import events
from polynav.runtime.task_robot import RuntimeTaskRobot
from polynav.runtime.task_schedules import TaskSchedules
from polynav.store.records import TaskRecord
from polynav.tasks import tree
from polynav.tasks.engine import Task, TaskEngine
from polynav.tasks.node import Node
from polynav.tasks.states import NodeState

if TYPE_CHECKING:
    from polynav.runtime.robot_runtime import RobotRuntime

log = logging.getLogger(__name__)

T = TypeVar("T")

INTERRUPTED = "interrupted: the robot restarted"
"""The note of a task that was running or paused when the robot stopped (see the module)."""


class TaskCommands:
    """One robot's tasks (``runtime.tasks``)."""

    def __init__(self, runtime: RobotRuntime) -> None:
        self._runtime = runtime
        self.robot = RuntimeTaskRobot(runtime)
        self.engine = TaskEngine(self.robot, on_change=self._changed)
        self.schedules = TaskSchedules(runtime, self.engine)

    def load(self) -> None:
        """Bring back the stored tasks and schedules (once, when the runtime is made; see the
        module docstring). A stored task that no longer builds (an action type gone) is
        logged and left in the store untouched."""
        store = self._runtime.store
        for record in store.tasks():
            try:
                root = tree.build(record.spec)
                task = Task(record.name, root, dict(record.blackboard or {}), owner=record.owner,
                            kind=record.kind, id=record.id, spec=record.spec)
            except PolynavError as exc:
                log.error("stored task %s (%r) not loaded: %s", record.id, record.name, exc)
                continue
            self.engine.add(task)
            if record.state in (NodeState.WORKING.value, NodeState.PAUSED.value):
                log.warning("task %s (%r) was %s when the robot stopped: cancelled, not run "
                            "again", task.id, task.name, record.state)
                self.engine.cancel(task.id)
                task.note = INTERRUPTED
                self.engine.refresh(task)
                self._save_state(task)
            elif record.state != NodeState.WAITTING.value or record.note:
                self._save_state(task)
        self.schedules.load()

    def _call(self, fn: Callable[[], T]) -> T:
        return self._runtime.run_between_ticks(fn)

    # -- reading (any thread) ----------------------------------------------------------------

    def get(self, task_id: str) -> dict[str, Any]:
        """A task's snapshot (:meth:`Task.describe`). Raises NotFound."""
        return self.engine.get(task_id)

    def list(self, owner: str | None = None, kind: str | None = None) -> list[dict[str, Any]]:
        return self.engine.snapshots(owner, kind)

    def running(self) -> dict[str, Any] | None:
        task = self.engine.running
        return None if task is None else task.snapshot

    # -- commands ------------------------------------------------------------------------------

    def create(self, spec: Mapping[str, Any], *, name: str | None = None,
               blackboard: Mapping[str, Any] | None = None, owner: str = "native",
               kind: str = "task", temporary: bool = False, start: bool = False
               ) -> dict[str, Any]:
        """Make a task from its tree's JSON form (:mod:`polynav.tasks.tree`), and start it
        with ``start``; its snapshot.

        Raises:
            InvalidRequest: anything wrong in the tree or the blackboard (nothing is made).
        """
        root = tree.build(spec)
        return self.create_from(root, name=name if name is not None else str(spec.get("name", "")),
                                blackboard=blackboard if blackboard is not None
                                else spec.get("blackboard") or {},
                                owner=owner, kind=kind, temporary=temporary, start=start,
                                spec=spec)

    def create_from(self, root: Node, *, name: str, blackboard: Mapping[str, Any] | None = None,
                    owner: str = "native", kind: str = "task", temporary: bool = False,
                    start: bool = False, spec: Mapping[str, Any] | None = None
                    ) -> dict[str, Any]:
        """Make a task of a tree built already (a dialect's own). See :meth:`create`; with
        ``spec`` (the JSON form ``root`` was built from) a task that is not temporary is
        stored.

        Raises:
            StorageError: the store failed (nothing is made).
        """
        task = Task(name, root, dict(blackboard or {}), owner=owner, kind=kind,
                    temporary=temporary, spec=None if spec is None else copy.deepcopy(dict(spec)))

        def run() -> Task:
            self._put(task)  # first: the root's first state change updates the stored row
            self.engine.add(task)
            if start:
                self.engine.start(task.id)
            return task

        return self._call(run).snapshot

    def start(self, task_id: str) -> dict[str, Any]:
        return self._call(lambda: self.engine.start(task_id)).snapshot

    def pause(self, task_id: str, node_id: str | None = None) -> dict[str, Any]:
        return self._call(lambda: self.engine.pause(task_id, node_id)).snapshot

    def resume(self, task_id: str, node_id: str | None = None) -> dict[str, Any]:
        return self._call(lambda: self.engine.resume(task_id, node_id)).snapshot

    def cancel(self, task_id: str, node_id: str | None = None) -> dict[str, Any]:
        return self._call(lambda: self.engine.cancel(task_id, node_id)).snapshot

    def cancel_running(self) -> dict[str, Any] | None:
        """Cancel the running task; its snapshot, ``None`` if none ran."""
        tasks = self._call(self.engine.cancel_all)
        return tasks[0].snapshot if tasks else None

    def set_loop(self, task_id: str, loop: bool, node_id: str | None = None) -> dict[str, Any]:
        """Set ``loop_flag`` of the root (stored with the task) or of a sequence node (for
        this run only: node ids are made anew when a stored task is rebuilt)."""

        def run() -> Task:
            task = self.engine.set_loop(task_id, loop, node_id)
            if node_id is None and task.spec is not None:
                task.spec = {**task.spec, "loop_flag": loop}
                self._put(task)
            return task

        return self._call(run).snapshot

    def replace(self, task_id: str, spec: Mapping[str, Any] | None = None, *,
                name: str | None = None, blackboard: Mapping[str, Any] | None = None
                ) -> dict[str, Any]:
        root = None if spec is None else tree.build(spec)

        def run() -> Task:
            task = self.engine.replace(task_id, root, name=name, blackboard=blackboard)
            if spec is not None:
                task.spec = copy.deepcopy(dict(spec))
            self._put(task)
            return task

        return self._call(run).snapshot

    def delete(self, task_id: str) -> None:
        """Forget a task that does not run, with its schedules.

        Raises:
            NotFound: no such task. Conflict: it runs.
        """

        def run() -> None:
            self.engine.delete(task_id)
            self._runtime.store.delete_task(task_id)
            self.schedules.forget_task(task_id)

        self._call(run)

    def trigger_waits(self, task_id: str | None = None) -> int:
        """Release the running task's waiting ``wait_req_action``s; how many waited.

        Raises:
            NotFound: no task ``task_id``. Conflict: ``task_id`` is not the running task.
        """

        def run() -> int:
            if task_id is not None:
                task = self.engine.find(task_id)
                if task is not self.engine.running:
                    raise Conflict(f"task {task_id} is {task.state.value}, not running: "
                                   "only the running task's waits can be triggered")
            return self.engine.trigger()

        return self._call(run)

    # -- the loop --------------------------------------------------------------------------

    def note(self, event: events.RuntimeEvent) -> None:
        self.robot.note(event)

    def tick(self, now: float) -> None:
        self.engine.tick(now)
        self.schedules.tick(now)

    def _changed(self, task: Task, node: Node, state: NodeState) -> None:
        if node is task.root:
            self._save_state(task)
        self._runtime.publish(events.TaskChanged(
            self._runtime.now(), task.id, task.name, task.owner, node.id, node.kind,
            state.value, node is task.root, node.result))

    # -- the store -----------------------------------------------------------------------------

    def _stored(self, task: Task) -> bool:
        return not task.temporary and task.spec is not None

    def _put(self, task: Task) -> None:
        """Store the task whole (made, replaced). Raises StorageError."""
        if self._stored(task):
            assert task.spec is not None
            self._runtime.store.put_task(TaskRecord(
                task.id, task.name, task.owner, task.kind, task.spec, dict(task.blackboard),
                task.state.value, task.note, self._runtime.calendar_iso()))

    def _save_state(self, task: Task) -> None:
        """Store the root's state (from the loop: a failing store is logged, not raised)."""
        if not self._stored(task):
            return
        try:
            self._runtime.store.set_task_state(task.id, task.state.value, task.note,
                                               self._runtime.calendar_iso())
        except StorageError as exc:
            log.error("task %s: state %s not stored: %s", task.id, task.state.value, exc)
