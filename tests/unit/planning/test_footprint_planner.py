"""The footprint planner: the grid route when the body can drive it, a lattice route when not."""

from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.errors import ConfigError
from polynav.footprint import Footprint
from polynav.geometry import Pose2D
from polynav.maps.costmap import Costmap, CostmapConfig
from polynav.planning import registry
from polynav.planning.errors import NoBodyRoute, NoPath
from polynav.planning.footprint_planner import (
    FootprintPlanner,
    LatticeConfig,
    drivable,
    route_poses,
)
from polynav.planning.grid_planner import GridPlanner, GridPlannerConfig
from tests.helpers.rooms import room

BODY = Footprint.rectangle(0.51, 0.43)
GAP_WALL = [(4.0, 0.2, 4.1, 2.15), (3.4, 1.9, 3.45, 3.0)]


def _costmap(boxes: list[tuple[float, float, float, float]], footprint: Footprint = BODY,
             length: float = 8.0, width: float = 8.0) -> Costmap:
    config = CostmapConfig(robot_radius=footprint.inscribed_radius,
                           inflation_radius=footprint.circumscribed_radius + 0.3,
                           obstacle_layer=False)
    return Costmap.from_map(room(length, width, boxes), config)


def test_a_disk_keeps_the_grid_planner_and_its_exact_path() -> None:
    disk = Footprint.circle(0.25)
    costmap = _costmap([(3.0, 1.0, 3.2, 5.0)], disk)
    start, goal = Pose2D(1.0, 3.0, 0.0), Pose2D(6.0, 3.5, 0.0)
    planner = registry.for_footprint(disk)
    assert type(planner) is GridPlanner
    expected = GridPlanner(GridPlannerConfig()).plan(costmap, start, goal)
    path = planner.plan(costmap, start, goal)
    np.testing.assert_array_equal(path.points, expected.points)
    assert path.cost == expected.cost


def test_a_polygon_gets_the_grid_route_unchanged_where_the_body_can_drive_it() -> None:
    costmap = _costmap([(3.0, 1.0, 3.2, 5.0)])
    start, goal = Pose2D(1.0, 3.0, 0.0), Pose2D(6.0, 3.5, 0.0)
    planner = registry.for_footprint(BODY)
    assert isinstance(planner, FootprintPlanner)
    path = planner.plan(costmap, start, goal)
    np.testing.assert_array_equal(path.points, GridPlanner().plan(costmap, start, goal).points)
    assert planner.lattice_plans == 0


def test_a_gap_reachable_only_turning_in_a_channel_is_routed_round() -> None:
    # With costs ignored, the grid route takes the channel and the gap; the body cannot.
    costmap = _costmap([*GAP_WALL, (4.0, 2.75, 4.1, 7.2)])
    config = GridPlannerConfig(cost_weight=0.0)
    start, goal = Pose2D(1.5, 2.45, 0.0), Pose2D(6.5, 2.45, 0.0)
    grid_path = GridPlanner(config).plan(costmap, start, goal)
    assert not drivable(grid_path, BODY, costmap, start.theta)
    planner = FootprintPlanner(BODY, config)
    path = planner.plan(costmap, start, goal)
    assert planner.lattice_plans == 1
    assert drivable(path, BODY, costmap, start.theta)
    assert path.points[0] == pytest.approx([start.x, start.y])
    assert path.points[-1] == pytest.approx([goal.x, goal.y])
    assert float(path.points[:, 1].max()) > 7.2  # round the wall's end
    assert path.length > grid_path.length + 2.0


def test_a_body_wider_than_every_way_gets_no_path_with_the_disk_route_and_where_it_touches(
) -> None:
    costmap = _costmap([*GAP_WALL, (4.0, 2.75, 4.1, 8.2)])
    with pytest.raises(NoBodyRoute) as err:
        FootprintPlanner(BODY).plan(costmap, Pose2D(1.5, 2.45, 0.0), Pose2D(6.5, 2.45, 0.0))
    assert isinstance(err.value, NoPath)
    # The disk's route goes through the channel and the gap; the body first touches there.
    assert err.value.route.points[-1] == pytest.approx([6.5, 2.45])
    assert 3.3 < err.value.blocked_at.x < 4.2


def test_route_poses_turn_in_place_at_corners_and_from_the_start_heading() -> None:
    points = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]])
    poses = route_poses(points, BODY, 0.05, start_theta=math.pi)
    assert poses[0, 2] == pytest.approx(math.pi)
    corner = poses[(np.hypot(poses[:, 0] - 1.0, poses[:, 1]) < 1e-9)]
    # At the corner the heading sweeps from 0 to pi/2 in steps of the body's rotation step.
    assert corner[:, 2].min() == pytest.approx(0.0)
    assert corner[:, 2].max() == pytest.approx(math.pi / 2)
    assert np.all(np.abs(np.diff(corner[:, 2])) <= BODY.rotation_step(0.05) + 1e-9)
    assert poses[-1, :2] == pytest.approx([1.0, 1.0])


def test_a_gate_barely_wider_than_the_body_is_left_for_a_way_with_room() -> None:
    # A wall across the room: a 0.46 m gate on the straight line (1.5 cm either side of the
    # 0.43 m body, no room for control to err) and a 1 m opening 1.6 m off it.
    wall = [(4.0, 0.2, 4.1, 1.0), (4.0, 2.0, 4.1, 3.37), (4.0, 3.83, 4.1, 6.2)]
    costmap = _costmap(wall, length=8.0, width=6.0)
    start, goal = Pose2D(1.5, 3.6, 0.0), Pose2D(6.5, 3.6, 0.0)
    path = FootprintPlanner(BODY).plan(costmap, start, goal)
    crossing = path.points[np.argmin(np.abs(path.points[:, 0] - 4.05))]
    assert 1.0 < crossing[1] < 2.0  # through the wide opening


def test_the_route_leaves_the_most_room_of_the_paddings_that_leaves_a_route() -> None:
    # A gap 0.59 m wide (8 cm either side of the body) on the straight line; open round the top.
    costmap = _costmap([(4.0, 0.0, 4.1, 2.15), (4.0, 2.74, 4.1, 6.5)])
    start, goal = Pose2D(1.0, 2.45, 0.0), Pose2D(7.0, 2.45, 0.0)
    tight = FootprintPlanner(BODY).plan(costmap, start, goal)
    assert float(tight.points[:, 1].max()) < 3.0  # through the gap
    roomy = FootprintPlanner(BODY, lattice_config=LatticeConfig(footprint_paddings=(0.15, 0.05)))
    path = roomy.plan(costmap, start, goal)
    assert float(path.points[:, 1].max()) > 6.5  # round the top, with 15 cm of room
    assert drivable(path, BODY.padded(0.15), costmap, start.theta)


def test_lattice_paddings_must_be_given_and_not_negative() -> None:
    for paddings in ((), (0.1, -0.05)):
        with pytest.raises(ConfigError):
            LatticeConfig(footprint_paddings=paddings)
