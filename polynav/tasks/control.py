"""The control nodes of a behavior tree (galileo-tasks-bt-ws §7.3), by their wire names.

A child's ``FAIL`` (or ``CANCELLED``: a subtree stopped on its own is a child that did not
succeed) lets the parent branch; a child's ``ERROR`` ends the parent ``ERROR`` and so, node by
node, the whole tree. Whatever restarts or loops does so at most once per tick, so a subtree
that ends at once (a chain of instant actions, an action failing at its start) cannot spin the
runtime's loop: it moves on at the next tick.
"""

from __future__ import annotations

from typing import Any, ClassVar

from polynav.errors import InvalidRequest
from polynav.tasks.node import Node, Run
from polynav.tasks.states import NodeState

_NOT_DONE = (NodeState.FAIL, NodeState.CANCELLED)


class Control(Node):
    """A node that runs children; ``arity`` is (least, most) children, most ``None``: any."""

    arity: ClassVar[tuple[int, int | None]] = (1, None)

    def __init__(self, children: list[Node], *, name: str = "", node_id: str | None = None
                 ) -> None:
        least, most = self.arity
        count = len(children)
        if count < least or (most is not None and count > most):
            wanted = f"exactly {least}" if least == most else f"at least {least}"
            raise InvalidRequest("sub_tasks", f"a {self.kind} node takes {wanted} "
                                              f"child{'ren' if least != 1 else ''}, got {count}")
        super().__init__(name=name, node_id=node_id, children=children)

    def params(self) -> dict[str, Any]:
        """The node's own parameters, as given."""
        return {}

    def describe(self) -> dict[str, Any]:
        return {**super().describe(), **self.params()}


class Sequence(Control):
    """Children in order: a ``FAIL`` fails it, all ``COMPLETE`` complete it. A plain task is a
    sequence; with ``loop_flag`` it starts over after each pass, counting ``loop_count``."""

    kind = "sequence"

    def __init__(self, children: list[Node], *, name: str = "", node_id: str | None = None,
                 loop_flag: bool = False) -> None:
        super().__init__(children, name=name, node_id=node_id)
        self.loop_flag = loop_flag
        self.index = 0
        self.loop_count = 0

    @property
    def current(self) -> Node | None:
        """The child running (or to run next) while the node works."""
        if self.state.active and self.index < len(self.children):
            return self.children[self.index]
        return None

    def update(self, run: Run) -> None:
        while self.index < len(self.children):
            state = self.children[self.index].tick(run)
            if state is NodeState.COMPLETE:
                self.index += 1
            elif state in _NOT_DONE:
                self.on_child_failed(run)
                return
            elif state is NodeState.ERROR:
                self.end(run, NodeState.ERROR)
                return
            else:
                return
        self.pass_done(run)

    def on_child_failed(self, run: Run) -> None:
        self.end(run, NodeState.FAIL)

    def pass_done(self, run: Run) -> None:
        """Every child completed."""
        if self.loop_flag:
            self.start_over()
        else:
            self.end(run, NodeState.COMPLETE)

    def start_over(self) -> None:
        self.loop_count += 1
        self.index = 0
        for child in self.children:
            child.reset()

    def reset(self) -> None:
        super().reset()
        self.index = 0
        self.loop_count = 0

    def params(self) -> dict[str, Any]:
        return {"loop_flag": self.loop_flag, "loop_count": self.loop_count}


class Loop(Sequence):
    """A sequence run ``target_loop_count`` times (0: for ever); a ``FAIL`` fails it."""

    kind = "loop"

    def __init__(self, children: list[Node], *, target_loop_count: int = 0, name: str = "",
                 node_id: str | None = None) -> None:
        if isinstance(target_loop_count, bool) or not isinstance(target_loop_count, int) \
                or target_loop_count < 0:
            raise InvalidRequest("target_loop_count", f"must be an integer >= 0 (0: for ever), "
                                                      f"got {target_loop_count!r}")
        super().__init__(children, name=name, node_id=node_id)
        self.target_loop_count = target_loop_count

    def pass_done(self, run: Run) -> None:
        if self.target_loop_count and self.loop_count + 1 >= self.target_loop_count:
            self.loop_count += 1
            self.end(run, NodeState.COMPLETE)
        else:
            self.start_over()

    def params(self) -> dict[str, Any]:
        return {"target_loop_count": self.target_loop_count, "loop_count": self.loop_count}


class RestartSequence(Sequence):
    """A sequence that starts again from its first child when a child fails (no limit)."""

    kind = "restart_sequence"

    def on_child_failed(self, run: Run) -> None:
        self.index = 0
        for child in self.children:
            child.reset()

    def params(self) -> dict[str, Any]:
        return {}


class RetrySequence(Sequence):
    """A sequence that runs a failed child again until it completes (no limit)."""

    kind = "retry_sequence"

    def on_child_failed(self, run: Run) -> None:
        self.children[self.index].reset()

    def params(self) -> dict[str, Any]:
        return {}


class Parallel(Control):
    """All children at once: ``COMPLETE`` once ``success_count`` of them completed (0: all of
    them, A-1: "reaches"), ``FAIL`` once that count can no longer be reached, ``ERROR`` when
    one errs; the children still running are cancelled when it ends."""

    kind = "parallel"

    def __init__(self, children: list[Node], *, success_count: int = 0, name: str = "",
                 node_id: str | None = None) -> None:
        super().__init__(children, name=name, node_id=node_id)
        if isinstance(success_count, bool) or not isinstance(success_count, int) \
                or not 0 <= success_count <= len(children):
            raise InvalidRequest("success_count", f"must be an integer in [0, {len(children)}] "
                                                  f"(0: every child), got {success_count!r}")
        self.success_count = success_count

    def update(self, run: Run) -> None:
        for child in self.children:
            if not child.state.final:
                child.tick(run)
        states = [child.state for child in self.children]
        needed = self.success_count or len(self.children)
        done = states.count(NodeState.COMPLETE)
        open_ = sum(1 for s in states if not s.final)
        if NodeState.ERROR in states:
            self.end(run, NodeState.ERROR)
        elif done >= needed:
            self.end(run, NodeState.COMPLETE)
        elif done + open_ < needed:
            self.end(run, NodeState.FAIL)

    def params(self) -> dict[str, Any]:
        return {"success_count": self.success_count}


class Fallback(Control):
    """Two children (A-25): the second runs only when the first fails."""

    kind = "fallback"
    arity = (2, 2)

    def __init__(self, children: list[Node], *, name: str = "", node_id: str | None = None
                 ) -> None:
        super().__init__(children, name=name, node_id=node_id)
        self.index = 0

    def update(self, run: Run) -> None:
        while self.index < len(self.children):
            state = self.children[self.index].tick(run)
            if state is NodeState.COMPLETE:
                self.end(run, NodeState.COMPLETE)
                return
            if state is NodeState.ERROR:
                self.end(run, NodeState.ERROR)
                return
            if state not in _NOT_DONE:
                return
            self.index += 1
        self.end(run, NodeState.FAIL)

    def reset(self) -> None:
        super().reset()
        self.index = 0


class Decorator(Control):
    """One child, its result turned into the node's by ``outcome``."""

    arity = (1, 1)
    #: The node's state for the child's COMPLETE and FAIL.
    outcome: ClassVar[dict[NodeState, NodeState]] = {}

    def update(self, run: Run) -> None:
        state = self.children[0].tick(run)
        if state is NodeState.ERROR:
            self.end(run, NodeState.ERROR)
        elif state is NodeState.COMPLETE:
            self.end(run, self.outcome[NodeState.COMPLETE])
        elif state in _NOT_DONE:
            self.end(run, self.outcome[NodeState.FAIL])


class Flip(Decorator):
    kind = "flip"
    outcome = {NodeState.COMPLETE: NodeState.FAIL, NodeState.FAIL: NodeState.COMPLETE}


class ForceFail(Decorator):
    kind = "force_fail"
    outcome = {NodeState.COMPLETE: NodeState.FAIL, NodeState.FAIL: NodeState.FAIL}


class ForceSuccess(Decorator):
    kind = "force_success"
    outcome = {NodeState.COMPLETE: NodeState.COMPLETE, NodeState.FAIL: NodeState.COMPLETE}


class RetryUntilSuccess(Control):
    """One child, run again each time it fails until it completes (no limit)."""

    kind = "retry_until_success"
    arity = (1, 1)

    def update(self, run: Run) -> None:
        child = self.children[0]
        state = child.tick(run)
        if state is NodeState.ERROR:
            self.end(run, NodeState.ERROR)
        elif state is NodeState.COMPLETE:
            self.end(run, NodeState.COMPLETE)
        elif state in _NOT_DONE:
            child.reset()


#: Control nodes by wire name.
CONTROLS: dict[str, type[Control]] = {
    cls.kind: cls for cls in (Sequence, Parallel, Fallback, Flip, Loop, ForceFail, ForceSuccess,
                              RestartSequence, RetrySequence, RetryUntilSuccess)
}
