"""``polynav world from-map``: worlds from MovingAI and ROS plans whose points are free, clear of
walls and reachable, deterministic for a seed; bad input is a clear error and writes nothing."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy import ndimage

from polynav.errors import InvalidRequest
from polynav.maps.costmap import Costmap, CostmapConfig
from polynav.planning.grid_planner import GridPlanner, GridPlannerConfig
from polynav.worlds import load_world
from polynav.worlds.from_map import FromMapOptions, write_world_from_map
from tests.conftest import DATA

ROOMS = DATA / "movingai" / "room-32-32-4.map"
NAV2 = DATA / "nav2" / "planner_benchmark" / "100by100_10.yaml"


def _check_world(folder: Path, options: FromMapOptions) -> None:
    world = load_world(folder)
    (floor,) = world.floors
    grid = floor.map
    info = grid.info
    free = grid.data == 0
    clearance = ndimage.distance_transform_edt(free) * info.resolution
    passable = clearance >= options.robot_radius + 0.5 * info.resolution
    labels, _ = ndimage.label(passable, structure=np.ones((3, 3), dtype=bool))
    cells = [info.world_to_cell(p.pose.x, p.pose.y) for p in floor.points]
    assert len(floor.points) == options.points + 1  # the initial point and the goals
    assert {labels[iy, ix] for ix, iy in cells} != {0}
    assert len({labels[iy, ix] for ix, iy in cells}) == 1  # one region: all reachable
    for ix, iy in cells:
        assert clearance[iy, ix] >= options.robot_radius + options.margin - 1e-9
    assert len(floor.people) <= options.walkers
    wide = 0.3 + 2.0 * options.robot_radius + options.margin  # the robot can pass them
    for route in floor.people:
        for x, y in route.waypoints:
            ix, iy = info.world_to_cell(x, y)
            assert passable[iy, ix] and clearance[iy, ix] >= wide
    assert (world.start_pose.x, world.start_pose.y) == (floor.points[0].pose.x,
                                                         floor.points[0].pose.y)
    # Reachable as the navigator sees it: the planner finds a way from the start to each point.
    costmap = Costmap.from_map(grid, CostmapConfig(obstacle_layer=False))
    planner = GridPlanner(GridPlannerConfig())
    for point in floor.points[1:]:
        assert planner.plan(costmap, world.start_pose, point.pose).length > 0.0


def test_a_movingai_map_becomes_a_world_of_reachable_cleared_points(tmp_path: Path) -> None:
    options = FromMapOptions(cell=1.0, points=12, walkers=2, seed=4)
    planned = write_world_from_map(ROOMS, tmp_path / "rooms", options)
    assert planned.grid.info.resolution == pytest.approx(0.05)
    assert planned.grid.info.width == 32 * 20 + 2  # 20 pixels a cell, and a wall round it
    _check_world(tmp_path / "rooms", options)


def test_a_ros_map_becomes_a_world_and_the_seed_decides_everything(tmp_path: Path) -> None:
    options = FromMapOptions(points=8, walkers=3, seed=9)
    first = write_world_from_map(NAV2, tmp_path / "a", options)
    again = write_world_from_map(NAV2, tmp_path / "b", options)
    other = write_world_from_map(NAV2, tmp_path / "c", FromMapOptions(points=8, seed=10))
    _check_world(tmp_path / "a", options)
    assert len(first.walkers) == 3  # open floor: every walker finds a stretch
    assert (first.points, first.walkers) == (again.points, again.walkers)
    assert first.points != other.points
    written = [(tmp_path / name / "world.yaml").read_text() for name in ("a", "b")]
    assert written[0] == written[1]


def _bad(tmp_path: Path, plan: Path, options: FromMapOptions, match: str) -> None:
    out = tmp_path / "out"
    with pytest.raises(InvalidRequest, match=match):
        write_world_from_map(plan, out, options)
    assert not out.exists()
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".out")] == []


def test_bad_input_is_a_clear_error_and_writes_nothing(tmp_path: Path) -> None:
    _bad(tmp_path, tmp_path / "nowhere.map", FromMapOptions(), "no such file")
    garbage = tmp_path / "garbage.map"
    garbage.write_text("type octile\nheight 3\nwidth two\nmap\n...\n")
    _bad(tmp_path, garbage, FromMapOptions(), "width")
    solid = tmp_path / "solid.map"
    solid.write_text("type octile\nheight 3\nwidth 3\nmap\n@@@\n@@@\n@@@\n")
    _bad(tmp_path, solid, FromMapOptions(), "no free space")
    _bad(tmp_path, DATA / "movingai" / "empty-8-8.map", FromMapOptions(points=500), "points fit")
    text = tmp_path / "plan.txt"
    text.write_text("hello")
    _bad(tmp_path, text, FromMapOptions(), "expected a ROS map")
    with pytest.raises(InvalidRequest):
        FromMapOptions(points=0)


def test_an_existing_folder_is_not_overwritten(tmp_path: Path) -> None:
    out = tmp_path / "out"
    out.mkdir()
    (out / "mine.txt").write_text("keep me")
    with pytest.raises(InvalidRequest, match="not an empty folder"):
        write_world_from_map(ROOMS, out, FromMapOptions(points=3))
    assert [p.name for p in out.iterdir()] == ["mine.txt"]
