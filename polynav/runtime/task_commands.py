"""The runtime's task commands: the task engine's commands between ticks, for every adapter.

Dialects create, read and control tasks only here (the engine itself is
:mod:`polynav.tasks.engine`); every command runs between ticks like the runtime's others, and
reads return the engine's snapshots without waiting for the loop. Each node's state change is
published as a :class:`~polynav.runtime.events.TaskChanged` event.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING, Any, TypeVar

from polynav.runtime import events
from polynav.runtime.task_robot import RuntimeTaskRobot
from polynav.tasks import tree
from polynav.tasks.engine import Task, TaskEngine
from polynav.tasks.node import Node
from polynav.tasks.states import NodeState

if TYPE_CHECKING:
    from polynav.runtime.robot_runtime import RobotRuntime

T = TypeVar("T")


class TaskCommands:
    """One robot's tasks (``runtime.tasks``)."""

    def __init__(self, runtime: RobotRuntime) -> None:
        self._runtime = runtime
        self.robot = RuntimeTaskRobot(runtime)
        self.engine = TaskEngine(self.robot, on_change=self._changed)

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
                                owner=owner, kind=kind, temporary=temporary, start=start)

    def create_from(self, root: Node, *, name: str, blackboard: Mapping[str, Any] | None = None,
                    owner: str = "native", kind: str = "task", temporary: bool = False,
                    start: bool = False) -> dict[str, Any]:
        """Make a task of a tree built already (a dialect's own). See :meth:`create`."""
        task = Task(name, root, dict(blackboard or {}), owner=owner, kind=kind,
                    temporary=temporary)

        def run() -> Task:
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
        return self._call(lambda: self.engine.set_loop(task_id, loop, node_id)).snapshot

    def replace(self, task_id: str, spec: Mapping[str, Any] | None = None, *,
                name: str | None = None, blackboard: Mapping[str, Any] | None = None
                ) -> dict[str, Any]:
        root = None if spec is None else tree.build(spec)
        return self._call(lambda: self.engine.replace(task_id, root, name=name,
                                                      blackboard=blackboard)).snapshot

    def delete(self, task_id: str) -> None:
        self._call(lambda: self.engine.delete(task_id))

    def trigger_waits(self) -> int:
        """Release the running task's waiting ``wait_req_action``s; how many waited."""
        return self._call(self.engine.trigger)

    # -- the loop --------------------------------------------------------------------------

    def note(self, event: events.RuntimeEvent) -> None:
        self.robot.note(event)

    def tick(self, now: float) -> None:
        self.engine.tick(now)

    def _changed(self, task: Task, node: Node, state: NodeState) -> None:
        self._runtime.publish(events.TaskChanged(
            self._runtime.now(), task.id, task.name, task.owner, node.id, node.kind,
            state.value, node is task.root, node.result))
