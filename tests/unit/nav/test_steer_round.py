"""A route the lidar closes ahead of a moving robot is steered round at once, not waited out."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from polynav.control.interface import ControlStatus
from polynav.geometry import Pose2D
from polynav.maps import costs
from polynav.nav.attempt import GoalOptions
from polynav.nav.navigator_config import NavigatorConfig
from polynav.planning.path import Path
from tests.unit.nav.test_navigator import FakeCostmap, Harness, ScriptedController, ScriptedPlanner

POST = (3.0, 0.0)


@dataclass
class DetourPlanner(ScriptedPlanner):
    """Straight to the goal, or round the post by 1 m once the post is marked."""

    costmap: FakeCostmap | None = None

    def plan(self, costmap: object, start: Pose2D, goal: Pose2D, *,
             goal_tolerance: float | None = None) -> Path:
        self.calls += 1
        assert self.costmap is not None
        ix, iy = self.costmap.info.world_to_cell(*POST)
        if self.costmap.costs[iy, ix] != costs.LETHAL:
            return Path(np.array([[start.x, start.y], [goal.x, goal.y]]))
        return Path(np.array([[start.x, start.y], [POST[0], 1.0], [goal.x, goal.y]]))


def _mark_post(h: Harness) -> None:
    ix, iy = h.costmap.info.world_to_cell(*POST)
    h.costmap.costs[iy, ix] = costs.LETHAL


def _harness(planner: ScriptedPlanner, statuses: list[ControlStatus]) -> Harness:
    h = Harness(planner, ScriptedController(statuses),
                NavigatorConfig(blocked_wait=1.5, closed_route_replan_period=100.0))
    if isinstance(planner, DetourPlanner):
        planner.costmap = h.costmap
    return h


def test_a_post_seen_on_the_route_ahead_is_steered_round_without_the_block_s_wait() -> None:
    planner = DetourPlanner()
    tracking = ControlStatus.TRACKING
    h = _harness(planner, [tracking] * 10 + [ControlStatus.BLOCKED] + [tracking])
    h.nav.start(Pose2D(8.0, 0.0, 0.0), h.now)
    h.run(0.2, move=True)
    _mark_post(h)  # the lidar sees a post on the route, 2.5 m ahead: the controller stops
    h.run(0.4, move=True)
    assert planner.calls == 2
    assert "NavigationBlocked" not in h.kinds() and "NavigationRetry" not in h.kinds()
    assert h.kinds()[-1] == "PathPlanned"
    assert h.nav.attempt is not None and h.nav.attempt.retries == 0
    assert h.twists[-1].linear > 0  # moving again the period after


def test_a_planner_that_takes_the_same_way_again_leaves_the_block_its_course() -> None:
    planner = ScriptedPlanner()  # straight through the post, whatever is marked
    h = _harness(planner, [ControlStatus.TRACKING] * 10 + [ControlStatus.BLOCKED] * 60
                 + [ControlStatus.TRACKING])
    h.nav.start(Pose2D(8.0, 0.0, 0.0), h.now)
    h.run(0.2, move=True)
    _mark_post(h)
    h.run(0.6, move=True)
    assert planner.calls == 2  # the steering plan, refused: it runs into the same post
    assert "NavigationBlocked" in h.kinds()
    assert all(t.linear == 0.0 for t in h.twists[-5:])


def test_a_caller_with_its_own_retry_limit_keeps_every_block() -> None:
    planner = DetourPlanner()
    h = _harness(planner, [ControlStatus.TRACKING] * 10 + [ControlStatus.BLOCKED] * 60
                 + [ControlStatus.TRACKING])
    h.nav.start(Pose2D(8.0, 0.0, 0.0), h.now, GoalOptions(max_retries=3))
    h.run(0.2, move=True)
    _mark_post(h)
    h.run(0.6, move=True)
    assert planner.calls == 1
    assert "NavigationBlocked" in h.kinds()
