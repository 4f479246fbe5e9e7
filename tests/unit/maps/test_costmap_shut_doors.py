"""Shut doors on the costmap: LETHAL to the body, not to the global planner.

A robot that had passed a fire door and let it close backed into its leaf (bench fleet, floor 2):
door leaves are passable to the lidar's marks, so the doorway looked free to every local move.
The leaves of doors that stand shut and that the robot is not opening are now drawn LETHAL on
the master (the body's view), while the planner plans on :meth:`Costmap.planning_costs`, the same
costs without them, so a route may still cross a door the robot will open on its way.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.footprint import Footprint
from polynav.geometry import Pose2D
from polynav.maps import costs
from polynav.maps.costmap import Costmap, CostmapConfig
from polynav.maps.keepout import VirtualWall
from polynav.maps.map import Map
from polynav.maps.raycast import cast_rays
from polynav.nav.passages import open_doors_on
from polynav.nav.recoveries import BackUp
from polynav.planning.path import Path
from polynav.robot.interface import LaserScan

RES = 0.05
# A 6 m x 4 m room cut in two by a wall at x = 3 m, with a 1 m doorway at y 1.5..2.5 m.
WEST_LEAF = VirtualWall(((3.0, 1.5), (3.0, 2.5)), 0.1)
# A second door far off, in the north wall's line (not a wall of this map: only a leaf).
NORTH_LEAF = VirtualWall(((5.0, 3.6), (5.5, 3.6)), 0.1)


def _walls() -> np.ndarray:
    walls = np.zeros((80, 120), dtype=bool)
    walls[0, :] = walls[-1, :] = walls[:, 0] = walls[:, -1] = True
    walls[:30, 60] = walls[50:, 60] = True  # x = 3 m, the doorway between y 1.5 and 2.5 m
    return walls


def _costmap() -> Costmap:
    grid = Map.from_occupied(_walls(), resolution=RES)
    return Costmap.from_map(grid, CostmapConfig(robot_radius=0.25, inflation_radius=0.6))


def _scan_from(walls: np.ndarray, costmap: Costmap, pose: Pose2D) -> LaserScan:
    angles = np.linspace(-math.pi, math.pi, 180, endpoint=False)
    ranges = cast_rays(walls, costmap.info, pose.x, pose.y, angles + pose.theta, 5.0)
    return LaserScan(0.0, -math.pi, angles[1] - angles[0], 0.05, 5.0, ranges.astype(np.float32))


def test_a_shut_leaf_is_lethal_to_the_body_and_free_to_the_planner() -> None:
    costmap, twin = _costmap(), _costmap()
    assert costmap.planning_costs() is costmap  # nothing shut: no copy
    doorway = twin.cost_at(3.0, 2.0)
    assert doorway < costs.INSCRIBED  # a 1 m doorway: the robot fits
    costmap.set_shut_doors([WEST_LEAF])
    assert costmap.shut_doors == (WEST_LEAF,)
    assert costmap.cost_at(3.0, 2.0) == costs.LETHAL
    assert costmap.cost_at(3.2, 2.0) >= costs.INSCRIBED  # inflated: the body keeps its radius
    assert costmap.cost_at(3.5, 2.0) > twin.cost_at(3.5, 2.0)
    planning = costmap.planning_costs()
    # The planner's costs are the costmap's without the leaf, cell for cell.
    np.testing.assert_array_equal(planning.costs, twin.costs)
    costmap.set_shut_doors([])
    np.testing.assert_array_equal(costmap.costs, twin.costs)
    assert costmap.planning_costs() is costmap


def test_the_planners_view_stays_the_costmap_without_the_leaves_as_scans_come() -> None:
    """Marks near and on the leaves, two doors apart: the recomposed windows match a twin
    costmap that never had shut doors, and the body's view is the twin's plus the leaves."""
    rng = np.random.default_rng(3)
    walls = _walls()
    costmap, twin = _costmap(), _costmap()
    costmap.set_shut_doors([WEST_LEAF, NORTH_LEAF])
    leaves_only = _costmap()
    leaves_only.set_keepouts([WEST_LEAF, NORTH_LEAF])
    for _ in range(12):
        world = walls.copy()
        for _ in range(3):  # people about, some by the doorway
            cx, cy = rng.integers(50, 110), rng.integers(10, 70)
            world[cy - 2:cy + 2, cx - 2:cx + 2] = True
        ix, iy = int(rng.integers(5, 115)), int(rng.integers(5, 75))
        if world[iy, ix]:
            continue
        x, y = costmap.info.cell_to_world(ix, iy)
        pose = Pose2D(x, y, float(rng.uniform(-math.pi, math.pi)))
        scan = _scan_from(world, costmap, pose)
        costmap.update_scan(pose, scan)
        twin.update_scan(pose, scan)
        np.testing.assert_array_equal(costmap.planning_costs().costs, twin.costs)
        # Where the twin is free of marks, the body's view is the leaves' (inflated).
        assert (costmap.costs >= np.minimum(twin.costs, leaves_only.costs)).all()
        assert costmap.cost_at(3.0, 2.0) == costs.LETHAL
        assert costmap.cost_at(5.25, 3.6) == costs.LETHAL


def test_a_route_through_a_shut_door_takes_that_leaf_off_the_body_view() -> None:
    costmap, twin = _costmap(), _costmap()
    costmap.set_shut_doors([WEST_LEAF, NORTH_LEAF])
    xs = np.arange(1.0, 5.0, 0.05)
    through_west = Path(np.column_stack((xs, np.full_like(xs, 2.0))))
    open_doors_on(costmap, through_west)
    assert costmap.shut_doors == (NORTH_LEAF,)  # the other stays shut to the body
    assert costmap.cost_at(3.0, 2.0) == twin.cost_at(3.0, 2.0)
    beside = Path(np.column_stack((np.full(20, 4.5), np.linspace(1.0, 3.0, 20))))
    open_doors_on(costmap, beside)
    assert costmap.shut_doors == (NORTH_LEAF,)


@pytest.mark.parametrize("shut", [False, True])
def test_backing_up_stops_before_a_shut_leaf_behind(shut: bool) -> None:
    """The robot passed the door eastward and let it close 0.45 m behind its centre."""
    costmap = _costmap()
    if shut:
        costmap.set_shut_doors([WEST_LEAF])
    back_up = BackUp(costmap, distance=0.6, speed=0.15, timeout=10.0,
                     footprint=Footprint.circle(0.25))
    pose = Pose2D(3.45, 2.0, 0.0)
    back_up.start(pose, 0.0)
    t = 0.0
    while (twist := back_up.tick(pose, t)) is not None:
        pose = Pose2D(pose.x + twist.linear * 0.05, pose.y, pose.theta)
        t += 0.05
    leaf_gap = pose.x - 3.0 - 0.25 - 0.05  # body edge to the leaf's face
    if shut:
        assert leaf_gap > 0.0
    else:
        assert leaf_gap < 0.0  # the doorway looked free: the body went into the leaf
