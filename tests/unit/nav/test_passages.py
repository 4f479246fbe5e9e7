"""Closed passages: noted where the body touches along the route, painted for the planner,
forgotten once seen free."""

from __future__ import annotations

import numpy as np

from polynav.control.tracked_path import TrackedPath
from polynav.footprint import Footprint
from polynav.geometry import Pose2D
from polynav.maps import costs
from polynav.maps.costmap import CostSnapshot
from polynav.maps.map import MapInfo
from polynav.nav.passages import ClosedPassages, touches_marks

BODY = Footprint.rectangle(0.51, 0.43)
INFO = MapInfo(resolution=0.05, width=100, height=60)


def _grid_with_post() -> CostSnapshot:
    grid = np.zeros((60, 100), dtype=np.uint8)
    grid[30, 60] = costs.LETHAL  # a post on the route, at (3.025, 1.525)
    return CostSnapshot(INFO, grid)


def _route() -> TrackedPath:
    return TrackedPath.from_points(np.array([[1.0, 1.5], [4.5, 1.5]]))


def test_a_block_closes_the_place_the_body_first_touches_along_the_route() -> None:
    passages = ClosedPassages(BODY, 60.0)
    passages.note_block(_grid_with_post(), _route(), 1.0, Pose2D(2.0, 1.5, 0.0))
    passage = passages.close(0.0)
    assert passage is not None
    assert 2.6 < passage.x < 2.8 and abs(passage.y - 1.5) < 1e-9
    assert passage.cells.tolist() == [[60, 30]]
    assert passages.tried == [passage.name]
    # The same place again is no new passage.
    passages.note_block(_grid_with_post(), _route(), 1.0, Pose2D(2.0, 1.5, 0.0))
    assert passages.close(0.0) is None


def test_a_block_with_nothing_on_the_route_closes_nothing() -> None:
    passages = ClosedPassages(BODY, 60.0)
    empty = CostSnapshot(INFO, np.zeros((60, 100), dtype=np.uint8))
    passages.note_block(empty, _route(), 1.0, Pose2D(2.0, 1.5, 0.0))
    assert passages.close(0.0) is None


def test_the_planning_grid_paints_the_closure_but_never_under_the_robot() -> None:
    passages = ClosedPassages(BODY, 60.0)
    passages.note_block(_grid_with_post(), _route(), 1.0, Pose2D(2.0, 1.5, 0.0))
    passage = passages.close(0.0)
    assert passage is not None
    robot = Pose2D(2.4, 1.5, 0.0)  # its nose reaches into the disc
    painted = passages.planning_grid(_grid_with_post(), robot).costs
    ix, iy = INFO.world_to_cell(passage.x + 0.15, passage.y)
    assert painted[iy, ix] == costs.LETHAL
    nose_x, nose_y = INFO.world_to_cell(robot.x + 0.25, robot.y)
    assert painted[nose_y, nose_x] == 0


def test_a_closure_is_forgotten_only_after_its_cells_stay_free() -> None:
    passages = ClosedPassages(BODY, 60.0, reopen_after=2.0)
    passages.note_block(_grid_with_post(), _route(), 1.0, Pose2D(2.0, 1.5, 0.0))
    assert passages.close(0.0) is not None
    free = CostSnapshot(INFO, np.zeros((60, 100), dtype=np.uint8))
    passages.refresh(free, 10.0)  # a recovery cleared the mark ...
    passages.refresh(_grid_with_post(), 10.1)  # ... and the next scan put it back
    passages.refresh(free, 11.0)
    passages.refresh(free, 12.5)
    assert len(passages.passages) == 1
    passages.refresh(free, 13.0)
    assert passages.passages == []
    assert len(passages.tried) == 1  # still named when the goal fails


def test_a_closure_stays_while_its_post_is_marked_in_a_neighbouring_cell() -> None:
    passages = ClosedPassages(BODY, 60.0, reopen_after=2.0)
    passages.note_block(_grid_with_post(), _route(), 1.0, Pose2D(2.0, 1.5, 0.0))
    assert passages.close(0.0) is not None
    wandered = np.zeros((60, 100), dtype=np.uint8)
    wandered[31, 60] = costs.LETHAL  # the same thin post, marked one cell over
    passages.refresh(CostSnapshot(INFO, wandered), 10.0)
    passages.refresh(CostSnapshot(INFO, wandered), 13.0)
    assert len(passages.passages) == 1
    gone = np.zeros((60, 100), dtype=np.uint8)
    gone[30, 63] = costs.LETHAL  # something three cells away: the passage is wider
    passages.refresh(CostSnapshot(INFO, gone), 14.0)
    passages.refresh(CostSnapshot(INFO, gone), 16.0)
    assert passages.passages == []


def test_no_passage_is_closed_once_the_time_budget_after_the_first_is_spent() -> None:
    passages = ClosedPassages(BODY, time_budget=60.0)
    passages.note_block(_grid_with_post(), _route(), 1.0, Pose2D(2.0, 1.5, 0.0))
    assert passages.close(10.0) is not None
    passages.reopen_all()  # the closure is gone; the budget still runs from it
    passages.note_block(_grid_with_post(), _route(), 1.0, Pose2D(2.0, 1.5, 0.0))
    assert passages.close(71.0) is None
    passages.note_block(_grid_with_post(), _route(), 1.0, Pose2D(2.0, 1.5, 0.0))
    assert passages.close(69.0) is not None


class _NoMap(CostSnapshot):
    """Live costs over a map that knows nothing (navigating without one)."""

    def map_cost_at(self, x: float, y: float) -> int:
        return costs.UNKNOWN


def test_a_mark_where_the_map_knows_nothing_is_a_mark_not_the_building() -> None:
    grid = _grid_with_post()
    on_post = Pose2D(3.025 - 0.2, 1.525, 0.0)  # the nose over the post
    assert touches_marks(_NoMap(grid.info, grid.costs), BODY, on_post)  # type: ignore[arg-type]
