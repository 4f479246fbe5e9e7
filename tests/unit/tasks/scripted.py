"""Leaves that end as a test says, and a robot that only keeps time, for the engine's tests."""

from __future__ import annotations

from typing import Any

from polynav.tasks.blackboard import Blackboard
from polynav.tasks.node import Node, Run
from polynav.tasks.states import NodeState

S = NodeState


class Scripted(Node):
    """A leaf that, each time it starts, works ``work`` ticks, then ends with the next of
    ``ends`` (the last one repeats)."""

    kind = "scripted"

    def __init__(self, *ends: NodeState, work: int = 0, name: str = "") -> None:
        super().__init__(name=name)
        self.ends = list(ends) or [S.COMPLETE]
        self.work = work
        self.starts = 0
        self.left = 0
        self.halted = 0
        self.held = 0

    def enter(self, run: Run) -> None:
        self.starts += 1
        self.left = self.work

    def update(self, run: Run) -> None:
        if self.left > 0:
            self.left -= 1
            return
        end = self.ends[min(self.starts, len(self.ends)) - 1]
        if end is not S.WORKING:
            self.end(run, end)

    def halt(self, run: Run) -> None:
        self.halted += 1

    def hold(self, run: Run) -> None:
        self.held += 1


class Clockwork:
    """A robot that keeps time and nothing else."""

    def __init__(self) -> None:
        self.t = 0.0
        self.settings: dict[str, Any] = {}
        self.said: list[str] = []

    def now(self) -> float:
        return self.t

    def change_settings(self, changes: dict[str, Any]) -> dict[str, Any]:
        old = {k: self.settings.get(k) for k in changes}
        self.settings.update(changes)
        return old

    def say(self, text: str) -> float:
        self.said.append(text)
        return 1.0

    def stop_speaking(self) -> None:
        pass


def run_of(robot: Clockwork | None = None, **values: Any) -> Run:
    return Run(robot or Clockwork(), Blackboard(values), "test")  # type: ignore[arg-type]


def tick_until_final(node: Node, run: Run, limit: int = 100) -> int:
    """Ticks until ``node`` ends; how many."""
    for i in range(1, limit + 1):
        if node.tick(run).final:
            return i
    raise AssertionError(f"{node.kind} still {node.state} after {limit} ticks")
