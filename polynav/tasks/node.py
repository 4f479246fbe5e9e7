"""A node of a task tree, and what the nodes of one running task share.

Every node, control or action, goes ``WAITTING`` -> ``WORKING`` (-> ``PAUSED`` -> ``WORKING``)
-> a final state. The engine ticks the root between the runtime's ticks; a node ticked while
``WAITTING`` starts (:meth:`Node.enter`), a ``WORKING`` node advances (:meth:`Node.update`), a
paused or ended node does nothing. A node that ends cancels whatever of its subtree still runs,
so nothing is left driving the robot behind an ended node.

Pause, resume and cancel work on any node, at any depth: pausing a node freezes its subtree
(its parent waits for it as for a running child); cancelling it ends its subtree
``CANCELLED``, and a parent takes a cancelled child as a failed one (a fallback branches).
"""

from __future__ import annotations

import logging
import uuid
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any, ClassVar

from polynav.tasks.blackboard import Blackboard
from polynav.tasks.robot import TaskRobot
from polynav.tasks.states import NodeState

log = logging.getLogger(__name__)


@dataclass
class Run:
    """What the nodes of one running task share: the robot, the blackboard and the time."""

    robot: TaskRobot
    blackboard: Blackboard
    task_id: str
    now: float = 0.0
    #: Set by an action whose robot was taken by another command: the task is cancelled.
    taken: str | None = None
    #: ``wait_req_action`` triggers not yet taken by a waiting action (the engine counts them).
    triggers: int = 0
    #: Settings to apply when the task ends, however it ends (``change_setting_action``).
    restore: list[dict[str, Any]] = field(default_factory=list)


class Node:
    """Base of control and action nodes."""

    #: The wire name of the node's kind (a control type or an action type).
    kind: ClassVar[str] = "node"

    def __init__(self, *, name: str = "", node_id: str | None = None,
                 children: list[Node] | None = None) -> None:
        self.id = node_id or str(uuid.uuid4())
        self.name = name
        self.children: list[Node] = list(children or [])
        self.state = NodeState.WAITTING
        self.result = ""

    # -- the tree ----------------------------------------------------------------------------

    def walk(self) -> Iterator[Node]:
        """This node and its subtree, depth first."""
        yield self
        for child in self.children:
            yield from child.walk()

    def find(self, node_id: str) -> Node | None:
        return next((n for n in self.walk() if n.id == node_id), None)

    @property
    def progress(self) -> float:
        """0-1: the share of the children done (actions say their own)."""
        if self.state is NodeState.COMPLETE:
            return 1.0
        if not self.children:
            return 0.0
        done = sum(1 for c in self.children if c.state is NodeState.COMPLETE)
        return round(done / len(self.children), 3)

    def describe(self) -> dict[str, Any]:
        """The node and its subtree as JSON values (the dialects pick their fields)."""
        return {"id": self.id, "name": self.name, "kind": self.kind, "state": self.state.value,
                "result": self.result, "progress": self.progress,
                "children": [c.describe() for c in self.children]}

    # -- running -----------------------------------------------------------------------------

    def tick(self, run: Run) -> NodeState:
        """Start or advance the node; its state after."""
        if self.state is NodeState.WAITTING:
            self.state = NodeState.WORKING
            self.enter(run)
        if self.state is NodeState.WORKING:
            self.update(run)
        return self.state

    def enter(self, run: Run) -> None:
        """Begin (the node has just become ``WORKING``); may end it at once."""

    def update(self, run: Run) -> None:
        """Advance a ``WORKING`` node; ends it with :meth:`end` when done."""

    def end(self, run: Run, state: NodeState, result: str | None = None) -> None:
        """End with ``state``, stopping whatever of the subtree still runs."""
        for child in self.children:
            if child.state.active:
                child.cancel(run)
        self.state = state
        if result is not None:
            self.result = result

    def pause(self, run: Run) -> bool:
        """Freeze the subtree; ``False`` if the node was not working."""
        if self.state is not NodeState.WORKING:
            return False
        for child in self.children:
            child.pause(run)
        self.hold(run)
        self.state = NodeState.PAUSED
        return True

    def resume(self, run: Run) -> bool:
        """Go on where :meth:`pause` left; ``False`` if the node was not paused."""
        if self.state is not NodeState.PAUSED:
            return False
        self.state = NodeState.WORKING
        self.carry_on(run)
        for child in self.children:
            child.resume(run)
        return True

    def cancel(self, run: Run) -> bool:
        """End the node and its subtree ``CANCELLED``, waiting nodes included; ``False`` if
        it had ended already."""
        if self.state.final:
            return False
        was_active = self.state.active
        for child in self.children:
            child.cancel(run)
        if was_active:
            self.halt(run)
        self.state = NodeState.CANCELLED
        return True

    def reset(self) -> None:
        """Back to ``WAITTING`` with its subtree, to run again (loops, retries)."""
        self.state = NodeState.WAITTING
        self.result = ""
        for child in self.children:
            child.reset()

    # -- what subclasses with something to stop override ------------------------------------

    def hold(self, run: Run) -> None:
        """Pause what the node itself drives."""

    def carry_on(self, run: Run) -> None:
        """Resume what the node itself drives."""

    def halt(self, run: Run) -> None:
        """Stop what the node itself drives (it is being cancelled)."""
