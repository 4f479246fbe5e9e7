"""Re-plans weigh routes by the time the controller takes over them, not their length alone: a
slot the body creeps through is slower than the roomy way beside it (issue 31, clutter courses
without a map)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from polynav.control.interface import ControlStatus
from polynav.control.tracked_path import TrackedPath
from polynav.footprint import Footprint
from polynav.geometry import Pose2D
from polynav.maps import costs
from polynav.nav.navigator_config import NavigatorConfig
from polynav.nav.route_choice import drive_length
from polynav.planning.path import Path
from tests.unit.nav.test_navigator import FakeCostmap, Harness, ScriptedController, ScriptedPlanner

BODY = Footprint.circle(0.25)
OPEN, LEAST = 0.3, 0.015  # a 2 m/s controller's pace at 0.15 s, and its 0.1 m/s floor
SLOT = [(4.0, 0.29), (4.0, -0.29)]  # two posts, 3.5 cm of room either side of the body


def _slot_costmap(grid: FakeCostmap | None = None) -> FakeCostmap:
    grid = grid or FakeCostmap()
    for x, y in SLOT:
        ix, iy = grid.info.world_to_cell(x, y)
        grid.costs[iy, ix] = costs.LETHAL
    return grid


STRAIGHT = np.array([[0.0, 0.0], [8.0, 0.0]])
ROOMY = np.array([[0.0, 0.0], [4.0, 1.5], [8.0, 0.0]])


def test_a_slot_counts_as_longer_than_its_length_and_the_open_as_its_length() -> None:
    grid = _slot_costmap()
    straight = TrackedPath.from_points(STRAIGHT)
    roomy = TrackedPath.from_points(ROOMY)
    assert drive_length(grid, BODY, straight, 0.0, open_clearance=0.0,
                        least_clearance=LEAST) == 8.0
    slow = drive_length(grid, BODY, straight, 0.0, open_clearance=OPEN, least_clearance=LEAST)
    assert slow > 10.0
    assert drive_length(grid, BODY, roomy, 0.0, open_clearance=OPEN,
                        least_clearance=LEAST) == np.float64(roomy.length)
    # Past the slot, what is left is open floor.
    assert drive_length(grid, BODY, straight, 5.0, open_clearance=OPEN,
                        least_clearance=LEAST) == 3.0


@dataclass
class SlotThenRoomy(ScriptedPlanner):
    """The straight way through the slot first, then the roomy way round it."""

    def plan(self, costmap: object, start: Pose2D, goal: Pose2D, *,
             goal_tolerance: float | None = None) -> Path:
        self.calls += 1
        if self.calls == 1:
            return Path(STRAIGHT.copy())
        return Path(np.array([[start.x, start.y], [4.0, 1.5], [goal.x, goal.y]]))


def _drive(config: NavigatorConfig) -> ScriptedController:
    controller = ScriptedController([ControlStatus.TRACKING])
    h = Harness(SlotThenRoomy(), controller, config)
    _slot_costmap(h.costmap)
    h.nav.start(Pose2D(8.0, 0.0, 0.0), h.now)
    h.run(1.2, move=True)
    return controller


def test_the_roomy_way_replaces_the_slot_at_the_next_re_plan() -> None:
    by_length = _drive(NavigatorConfig(replan_period=1.0))
    assert by_length.paths == 1  # 0.5 m longer: kept by the length hysteresis
    by_time = _drive(NavigatorConfig(replan_period=1.0, route_open_clearance=OPEN,
                                     route_least_clearance=LEAST))
    assert by_time.paths == 2
