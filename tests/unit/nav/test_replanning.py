"""Periodic re-planning: the next stretch spliced onto the route, the whole way now and then."""

from __future__ import annotations

import numpy as np

from polynav.control.tracked_path import TrackedPath
from polynav.geometry import Pose2D
from polynav.maps.costmap import Costmap, CostmapConfig
from polynav.maps.map import Map
from polynav.nav.replanning import PeriodicReplan, spliced
from polynav.planning.grid_planner import GridPlanner
from polynav.planning.path import Path


class CountingPlanner(GridPlanner):
    """The real grid planner, remembering the goals it was asked for."""

    def __init__(self) -> None:
        super().__init__()
        self.goals: list[Pose2D] = []

    def plan(self, costmap, start, goal, *, goal_tolerance=None):  # type: ignore[no-untyped-def]
        self.goals.append(goal)
        return super().plan(costmap, start, goal, goal_tolerance=goal_tolerance)


def _hall(post: bool = False) -> Costmap:
    """A 30 m x 6 m hall, with a post across the middle of the line y = 3 m when ``post``."""
    walls = np.zeros((120, 600), dtype=bool)
    walls[0, :] = walls[-1, :] = walls[:, 0] = walls[:, -1] = True
    if post:
        walls[50:70, 95:105] = True  # 0.5 m x 1 m, 5 m along
    grid = Map.from_occupied(walls, resolution=0.05, origin=Pose2D(0.0, 0.0, 0.0))
    return Costmap.from_map(grid, CostmapConfig(track_unknown=False))


ROUTE = TrackedPath.from_points([[1.0, 3.0], [29.0, 3.0]])
GOAL = Pose2D(29.0, 3.0, 0.0)


def test_spliced_route_is_the_stretch_then_the_rest_of_the_route() -> None:
    stretch = Path(np.array([[1.0, 3.0], [3.0, 4.0], [5.0, 3.0]]), cost=4.6)
    path = spliced(stretch, ROUTE, 4.0)
    assert path.points.tolist() == [[1.0, 3.0], [3.0, 4.0], [5.0, 3.0], [29.0, 3.0]]
    assert path.cost == 4.6 + 24.0


def test_near_replans_rejoin_the_route_ahead_and_route_round_what_was_seen() -> None:
    planner = CountingPlanner()
    replan = PeriodicReplan(planner, reach=8.0, full_period=15.0)
    replan.whole_way_planned(0.0)
    costmap = _hall(post=True)
    path = replan.plan(costmap, Pose2D(1.0, 3.0, 0.0), GOAL, ROUTE, 0.0, 3.0,
                       goal_tolerance=None)
    assert planner.goals[-1].x == 9.0 and planner.goals[-1].y == 3.0  # 8 m along the route
    assert np.allclose(path.points[-1], [29.0, 3.0])
    # Round the post: nowhere within the post or its inflation.
    route = TrackedPath.from_points(path.points)
    s = np.arange(0.0, route.length, 0.05)
    xy = route.points_at(s)
    near_post = (np.abs(xy[:, 0] - 5.0) < 0.3) & (np.abs(xy[:, 1] - 3.0) < 0.5)
    assert not near_post.any()
    assert 28.0 < path.length < 30.0


def test_the_whole_way_is_planned_every_full_period_near_the_end_and_when_the_stretch_fails(
) -> None:
    planner = CountingPlanner()
    replan = PeriodicReplan(planner, reach=8.0, full_period=15.0)
    replan.whole_way_planned(0.0)
    costmap = _hall()
    start = Pose2D(1.0, 3.0, 0.0)
    replan.plan(costmap, start, GOAL, ROUTE, 0.0, 3.0, goal_tolerance=None)
    assert planner.goals[-1].x == 9.0
    replan.plan(costmap, start, GOAL, ROUTE, 0.0, 15.0, goal_tolerance=None)
    assert planner.goals[-1] == GOAL  # the full period is up
    replan.plan(costmap, start, GOAL, ROUTE, 0.0, 18.0, goal_tolerance=None)
    assert planner.goals[-1].x == 9.0  # and restarts from the whole-way plan
    replan.plan(costmap, Pose2D(23.0, 3.0, 0.0), GOAL, ROUTE, 22.0, 21.0, goal_tolerance=None)
    assert planner.goals[-1] == GOAL  # less than the reach left: the whole way is near
    # The stretch's end is inside a wall: the whole way instead, in the same call.
    blocked = _hall()
    walled = TrackedPath.from_points([[1.0, 3.0], [9.0, 0.0], [29.0, 3.0]])
    path = replan.plan(blocked, start, GOAL, walled, 0.0, 24.0, goal_tolerance=None)
    assert planner.goals[-1] == GOAL and np.allclose(path.points[-1], [29.0, 3.0])
    # Reach 0: always the whole way.
    always = PeriodicReplan(planner, reach=0.0, full_period=15.0)
    always.whole_way_planned(0.0)
    always.plan(costmap, start, GOAL, ROUTE, 0.0, 3.0, goal_tolerance=None)
    assert planner.goals[-1] == GOAL


def test_after_a_detour_round_people_every_replan_plans_the_whole_way_for_a_while() -> None:
    planner = CountingPlanner()
    replan = PeriodicReplan(planner, reach=8.0, full_period=30.0, watch_for=10.0)
    replan.whole_way_planned(0.0)
    costmap = _hall()
    start = Pose2D(1.0, 3.0, 0.0)
    replan.watch(3.0)  # people closed the route at t = 3 s: a way round them was taken
    for now in (6.0, 9.0, 12.0):
        replan.plan(costmap, start, GOAL, ROUTE, 0.0, now, goal_tolerance=None)
        assert planner.goals[-1] == GOAL  # the way they closed may be open again
    replan.plan(costmap, start, GOAL, ROUTE, 0.0, 15.0, goal_tolerance=None)
    assert planner.goals[-1].x == 9.0  # the watch is over: near stretches again
