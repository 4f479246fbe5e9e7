"""A patrol's tree: failed legs are skipped, the very last leg decides, rounds are counted."""

from __future__ import annotations

import itertools

import pytest

from polynav.errors import InvalidRequest
from polynav.geometry import Pose2D
from polynav.nav.attempt import GoalOptions
from polynav.tasks.patrol import FOREVER, PatrolPlan, PatrolState, patrol_tree
from polynav.tasks.robot import GoalEnd, GoalOutcome
from polynav.tasks.states import NodeState
from tests.unit.tasks.scripted import Clockwork, run_of, tick_until_final


class Legs(Clockwork):
    """Goals that end at once: failed for the points in ``failing``."""

    def __init__(self, failing: set[str] = frozenset()) -> None:  # type: ignore[assignment]
        super().__init__()
        self.failing = failing
        self.visits: list[str] = []
        self.options: list[GoalOptions | None] = []
        self._ids = itertools.count(1)
        self._goals: dict[int, str] = {}

    def navigate(self, *, point: str | None = None, pose: Pose2D | None = None,
                 map_name: str | None = None, options: GoalOptions | None = None) -> int:
        assert point is not None
        attempt = next(self._ids)
        self._goals[attempt] = point
        self.visits.append(point)
        self.options.append(options)
        return attempt

    def goal_outcome(self, attempt_id: int) -> GoalOutcome:
        failed = self._goals[attempt_id] in self.failing
        return GoalOutcome(GoalEnd.FAILED if failed else GoalEnd.SUCCEEDED, "no path")

    def pose(self) -> Pose2D:
        return Pose2D(0.0, 0.0, 0.0)


@pytest.mark.parametrize(("count", "failing", "state", "visits"), [
    (1, set(), NodeState.COMPLETE, "abc"),
    (2, set(), NodeState.COMPLETE, "abcabc"),
    (2, {"b"}, NodeState.COMPLETE, "abcabc"),   # a failed leg is skipped
    (2, {"c"}, NodeState.FAIL, "abcabc"),       # the very last leg decides
    (3, {"a", "b"}, NodeState.COMPLETE, "abcabcabc"),
])
def test_patrol_rounds(count: int, failing: set[str], state: NodeState, visits: str) -> None:
    robot = Legs(failing)
    tree = patrol_tree(PatrolPlan(("a", "b", "c"), count=count, tolerance=0.4),
                       GoalOptions(max_retries=2))
    tick_until_final(tree, run_of(robot))
    assert tree.state is state
    assert "".join(robot.visits) == visits
    assert all(o is not None and o.pass_tolerance == 0.4 and o.max_retries == 2
               for o in robot.options)


def test_a_patrol_for_ever_goes_on_past_failures() -> None:
    robot = Legs({"a", "b"})
    tree = patrol_tree(PatrolPlan(("a", "b"), count=FOREVER))
    run = run_of(robot)
    for _ in range(20):
        tree.tick(run)
    assert tree.state is NodeState.WORKING and len(robot.visits) >= 10


def test_patrol_states_from_the_task() -> None:
    assert PatrolState.of(NodeState.WORKING) is PatrolState.RUNNING
    assert PatrolState.of(NodeState.COMPLETE) is PatrolState.SUCCEEDED
    assert PatrolState.of(NodeState.FAIL) is PatrolState.FAILED
    assert PatrolState.of(NodeState.CANCELLED) is PatrolState.CANCELED


@pytest.mark.parametrize(("points", "count", "tolerance"), [
    (("a",), 1, 0.5), (("a", "b"), 0, 0.5), (("a", "b"), 1, 0.0)])
def test_bad_plans(points: tuple[str, ...], count: int, tolerance: float) -> None:
    with pytest.raises(InvalidRequest):
        PatrolPlan(points, count=count, tolerance=tolerance)
