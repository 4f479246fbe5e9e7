"""A patrol: rounds over named points (a Yunji cruise), as a task tree for the engine.

A failed leg is skipped: the robot goes on to the next point (vendors' cruises do the same),
and the patrol as a whole fails only when its very last leg fails. ``count`` rounds of every
point, or ``FOREVER`` until cancelled. Each leg passes its point within ``tolerance`` and heads
on (a ``none_stop_nav_action``; a charger point is docked onto).

The tree: every leg but the very last one under ``force_success``; the rounds before the last
one in a ``loop``; the last round a sequence whose last leg decides the patrol.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass

from polynav.errors import InvalidRequest
from polynav.nav.attempt import GoalOptions
from polynav.tasks.actions.navigation import NoneStopNavAction
from polynav.tasks.control import ForceSuccess, Loop, Sequence
from polynav.tasks.node import Node
from polynav.tasks.states import NodeState

FOREVER = -1


class PatrolState(enum.Enum):
    RUNNING = "running"
    SUCCEEDED = "succeeded"
    FAILED = "failed"
    CANCELED = "canceled"

    @classmethod
    def of(cls, state: NodeState) -> PatrolState:
        """The patrol's state for its task's."""
        if state.active or state is NodeState.WAITTING:
            return cls.RUNNING
        if state is NodeState.COMPLETE:
            return cls.SUCCEEDED
        return cls.CANCELED if state is NodeState.CANCELLED else cls.FAILED


@dataclass(frozen=True, slots=True)
class PatrolPlan:
    """What to patrol: ``points`` in order, ``count`` rounds (``FOREVER``: -1), and how close
    [m] the robot must pass each point before heading for the next."""

    points: tuple[str, ...]
    count: int = 1
    tolerance: float = 0.5

    def __post_init__(self) -> None:
        if len(self.points) < 2:
            raise InvalidRequest("points", f"needs at least 2 points, got {len(self.points)}")
        if self.count != FOREVER and self.count < 1:
            raise InvalidRequest("count", f"must be >= 1 or -1 (forever), got {self.count}")
        if not self.tolerance > 0.0:
            raise InvalidRequest("tolerance", f"must be > 0, got {self.tolerance}")


def patrol_tree(plan: PatrolPlan, options: GoalOptions | None = None) -> Node:
    """The task tree of ``plan``; ``options`` apply to every leg (retries)."""

    def legs(last_round: bool) -> list[Node]:
        out: list[Node] = []
        for i, point in enumerate(plan.points):
            leg = NoneStopNavAction({"point": point, "radius": plan.tolerance}, options=options,
                                    name=point)
            decides = last_round and i == len(plan.points) - 1
            out.append(leg if decides else ForceSuccess([leg], name=point))
        return out

    if plan.count == FOREVER:
        return Loop(legs(False), target_loop_count=0, name="patrol")
    last = Sequence(legs(True), name="patrol" if plan.count == 1 else "last round")
    if plan.count == 1:
        return last
    rounds = Loop(legs(False), target_loop_count=plan.count - 1, name="rounds")
    return Sequence([rounds, last], name="patrol")
