from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
import pytest

from polynav.errors import ConfigError, InvalidRequest
from polynav.geometry import Pose2D
from polynav.maps import costs
from polynav.maps.ascii import map_from_ascii
from polynav.maps.costmap import Costmap, CostmapConfig, CostSnapshot
from polynav.maps.interface import CostGrid, Window
from polynav.maps.keepout import CircleZone, ForbiddenZone, VirtualWall
from polynav.maps.layers import window as win
from polynav.maps.map import Map, MapInfo
from polynav.maps.raycast import cast_rays
from polynav.robot.interface import LaserScan

# No inflation: the master shows exactly what static, keepout and obstacle layers wrote.
BARE = CostmapConfig(robot_radius=0.0, inflation_radius=0.0)
DEFAULT = CostmapConfig()
AT_ORIGIN = Pose2D()
FREE, INSCRIBED, LETHAL, UNKNOWN = costs.FREE, costs.INSCRIBED, costs.LETHAL, costs.UNKNOWN


def free_map(width: int = 41, height: int = 41, resolution: float = 0.1) -> Map:
    return Map.from_occupied(np.zeros((height, width), dtype=bool), resolution=resolution)


def scan(
    beams: dict[float, float],
    *,
    range_min: float = 0.05,
    range_max: float = 20.0,
    sensor_pose: Pose2D = AT_ORIGIN,
) -> LaserScan:
    """A scan holding the given {angle: range} beams (angles on a 1 mrad grid), inf elsewhere."""
    increment = 1e-3
    first = min(beams)
    count = round((max(beams) - first) / increment) + 1
    ranges = np.full(count, np.inf, dtype=np.float32)
    for angle, r in beams.items():
        ranges[round((angle - first) / increment)] = r
    return LaserScan(0.0, first, increment, range_min, range_max, ranges, sensor_pose)


def full_recomposition(costmap: Costmap) -> npt.NDArray[np.uint8]:
    """What the master would be if every layer redrew the whole grid now."""
    info = costmap.info
    default = UNKNOWN if costmap.config.track_unknown else FREE
    master = np.full((info.height, info.width), default, dtype=np.uint8)
    for layer in costmap.layers:
        layer.update_costs(master, win.full(info.width, info.height))
    return master


# --- configuration ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("kwargs", "key"),
    [
        ({"robot_radius": -0.1}, "costmap.robot_radius"),
        ({"robot_radius": 0.6}, "costmap.inflation_radius"),
        ({"inflation_radius": 0.2}, "costmap.inflation_radius"),
        ({"inflation_radius": math.inf}, "costmap.inflation_radius"),
        ({"cost_scaling_factor": -1.0}, "costmap.cost_scaling_factor"),
        ({"lethal_threshold": 0}, "costmap.lethal_threshold"),
        ({"lethal_threshold": 101}, "costmap.lethal_threshold"),
        ({"obstacle_max_range": 0.0}, "costmap.obstacle_max_range"),
        ({"raytrace_max_range": -1.0}, "costmap.raytrace_max_range"),
        ({"raytrace_max_range": math.nan}, "costmap.raytrace_max_range"),
        ({"inscribed_cell_margin": 1.5}, "costmap.inscribed_cell_margin"),
    ],
)
def test_config_rejects_out_of_range_values_naming_the_key(
    kwargs: dict[str, float], key: str
) -> None:
    with pytest.raises(ConfigError) as caught:
        CostmapConfig(**kwargs)  # type: ignore[arg-type]
    assert caught.value.key == key


# --- static layer and inflation --------------------------------------------------------------


def single_obstacle_costmap(config: CostmapConfig = DEFAULT) -> Costmap:
    occupied = np.zeros((31, 31), dtype=bool)
    occupied[15, 15] = True
    return Costmap.from_map(Map.from_occupied(occupied, resolution=0.05), config)


def test_costs_along_a_row_from_a_single_obstacle_follow_nav2_inflation() -> None:
    # robot_radius 0.25 m = 5 cells, inflation_radius 0.55 m = 11 cells, scaling 3.0:
    # cost = int(252 * exp(-3 (d - 0.25))) between the radii.
    row = single_obstacle_costmap().costs[15, 15:]
    expected = [LETHAL, 253, 253, 253, 253, 253, 216, 186, 160, 138, 119, 102, 0, 0, 0, 0]
    assert row.tolist() == expected
    assert single_obstacle_costmap().costs[15, :16].tolist() == expected[::-1]


def test_costs_off_axis_use_euclidean_cell_distance() -> None:
    c = single_obstacle_costmap().costs
    assert c[15 + 3, 15 + 4] == INSCRIBED  # 5 cells exactly
    assert c[15 + 4, 15 + 4] == 228  # sqrt(32) cells = 0.283 m
    assert c[15 + 1, 15 + 5] == 248  # sqrt(26) cells = 0.255 m
    assert c[15 - 5, 15 - 6] == 165  # sqrt(61) cells = 0.391 m
    assert c[15 + 6, 15 - 6] == 149  # sqrt(72) cells = 0.424 m
    assert c[15 + 8, 15 + 8] == FREE  # 0.566 m, beyond the inflation radius


def test_inscribed_ring_is_exactly_the_cells_within_the_robot_radius() -> None:
    c = single_obstacle_costmap().costs
    iy, ix = np.mgrid[0:31, 0:31]
    d2 = (ix - 15) ** 2 + (iy - 15) ** 2
    np.testing.assert_array_equal(c == INSCRIBED, (d2 > 0) & (d2 <= 25))
    np.testing.assert_array_equal(c == LETHAL, d2 == 0)


def test_an_inscribed_cell_margin_widens_the_inscribed_ring_by_that_share_of_a_cell() -> None:
    c = single_obstacle_costmap(CostmapConfig(inscribed_cell_margin=0.5)).costs
    iy, ix = np.mgrid[0:31, 0:31]
    d2 = (ix - 15) ** 2 + (iy - 15) ** 2
    np.testing.assert_array_equal(c == INSCRIBED, (d2 > 0) & (d2 <= 30))  # 5.5 cells


def test_steeper_scaling_factor_lowers_the_decay_costs() -> None:
    c = single_obstacle_costmap(CostmapConfig(cost_scaling_factor=10.0)).costs
    assert c[15, 15 + 6] == int(252 * math.exp(-10.0 * 0.05))  # 152


def test_unknown_map_cells_are_free_unless_unknown_is_tracked() -> None:
    grid = map_from_ascii("??..#", resolution=0.05)
    assert Costmap.from_map(grid, BARE).costs.tolist() == [[0, 0, 0, 0, LETHAL]]
    tracked = CostmapConfig(robot_radius=0.0, inflation_radius=0.0, track_unknown=True)
    assert Costmap.from_map(grid, tracked).costs.tolist() == [[UNKNOWN, UNKNOWN, 0, 0, LETHAL]]


def test_inflation_leaves_unknown_cells_unknown() -> None:
    grid = map_from_ascii("??#..", resolution=0.05)
    c = Costmap.from_map(grid, CostmapConfig(track_unknown=True)).costs
    assert c.tolist() == [[UNKNOWN, UNKNOWN, LETHAL, INSCRIBED, INSCRIBED]]


def test_occupancy_at_the_lethal_threshold_is_lethal_and_below_it_free() -> None:
    data = np.array([[64, 65, 99, 100, 30]], dtype=np.int8)
    grid = Map(MapInfo(resolution=0.1, width=5, height=1), data)
    assert Costmap.from_map(grid, BARE).costs.tolist() == [[0, LETHAL, LETHAL, LETHAL, 0]]
    config = CostmapConfig(robot_radius=0.0, inflation_radius=0.0, lethal_threshold=30)
    assert Costmap.from_map(grid, config).costs.tolist() == [[LETHAL] * 5]


# --- keepouts --------------------------------------------------------------------------------


def test_virtual_wall_is_lethal_and_inflated_like_a_wall() -> None:
    costmap = Costmap.from_map(free_map(resolution=0.05), CostmapConfig())
    costmap.set_keepouts([VirtualWall(points=((0.0, 1.025), (2.05, 1.025)), thickness=0.0)])
    c = costmap.costs
    assert (c[20, :] == LETHAL).all()
    assert c[20 + 5, 10] == INSCRIBED and c[20 - 6, 10] == 216 and c[20 + 12, 10] == FREE


def test_keepout_over_unknown_cells_is_lethal() -> None:
    config = CostmapConfig(robot_radius=0.0, inflation_radius=0.0, track_unknown=True)
    costmap = Costmap.from_map(map_from_ascii("???.", resolution=1.0), config)
    costmap.set_keepouts([CircleZone(x=1.5, y=0.5, radius=0.4)])
    assert costmap.costs.tolist() == [[UNKNOWN, LETHAL, UNKNOWN, FREE]]


def test_replacing_keepouts_removes_the_old_ones() -> None:
    costmap = Costmap.from_map(free_map(), CostmapConfig())
    before = costmap.costs.copy()
    zone = ForbiddenZone(polygon=((1.0, 1.0), (2.0, 1.0), (2.0, 2.0), (1.0, 2.0)))
    costmap.set_keepouts([zone])
    assert costmap.costs[15, 15] == LETHAL
    assert costmap.keepouts == (zone,)
    costmap.set_keepouts([])
    np.testing.assert_array_equal(costmap.costs, before)


# --- obstacle layer --------------------------------------------------------------------------

ROBOT = Pose2D(2.05, 2.05, 0.0)  # centre of cell (20, 20) on a 0.1 m grid


def test_scan_marks_the_hit_cell_lethal_and_clears_the_beam() -> None:
    config = CostmapConfig(robot_radius=0.0, inflation_radius=0.0, track_unknown=True)
    costmap = Costmap.from_map(map_from_ascii("?" * 41 + "\n" + "?" * 41, resolution=0.1), config)
    costmap.update_scan(Pose2D(2.05, 0.05, 0.0), scan({0.0: 1.0}))
    row = costmap.costs[0]
    assert row[30] == LETHAL
    assert (row[20:30] == FREE).all()
    assert row[19] == UNKNOWN and row[31] == UNKNOWN


def test_obstacles_are_inflated_like_map_walls() -> None:
    costmap = Costmap.from_map(free_map(resolution=0.05), CostmapConfig())
    costmap.update_scan(Pose2D(0.525, 1.025, 0.0), scan({0.0: 0.5}))
    assert costmap.costs[20, 20] == LETHAL
    assert costmap.costs[20, 20 - 5] == INSCRIBED and costmap.costs[20, 20 + 6] == 216


def test_map_cost_leaves_out_the_lidar_marks_but_keeps_walls_keepouts_and_inflation() -> None:
    # The navigator's question before waiting for a goal to clear: is it held by the building?
    occupied = np.zeros((41, 41), dtype=bool)
    occupied[:, 0] = True  # a wall along x = 0
    costmap = Costmap.from_map(Map.from_occupied(occupied, resolution=0.05), CostmapConfig())
    costmap.set_keepouts([CircleZone(x=1.525, y=1.525, radius=0.1)])
    costmap.update_scan(Pose2D(0.525, 1.025, 0.0), scan({0.0: 0.5}))  # something at (1.025, 1.025)
    assert costmap.cost_at(1.025, 1.025) == LETHAL
    assert costmap.map_cost_at(1.025, 1.025) == FREE
    assert costmap.map_cost_at(0.025, 1.025) == LETHAL  # the wall
    assert costmap.map_cost_at(0.225, 1.025) == INSCRIBED  # within a robot radius of it
    assert costmap.map_cost_at(0.225, 1.025) == full_recomposition_without_lidar(costmap)[20, 4]
    assert costmap.map_cost_at(1.525, 1.525) == LETHAL  # the keepout
    assert costmap.map_cost_at(-1.0, 1.0) == LETHAL  # off the map
    wide = full_recomposition_without_lidar(costmap)
    for x, y in [(0.4, 0.4), (0.3, 1.9), (1.3, 1.4), (1.9, 0.1)]:
        ix, iy = costmap.info.world_to_cell(x, y)
        assert costmap.map_cost_at(x, y) == wide[iy, ix]


def test_map_costs_are_the_whole_grid_from_the_map_and_keepouts_without_the_lidar_marks() -> None:
    # The navigator's question when no way is found: does the building have one?
    occupied = np.zeros((41, 41), dtype=bool)
    occupied[:, 0] = True
    costmap = Costmap.from_map(Map.from_occupied(occupied, resolution=0.05), CostmapConfig())
    costmap.set_keepouts([CircleZone(x=1.525, y=1.525, radius=0.1)])
    costmap.update_scan(Pose2D(0.525, 1.025, 0.0), scan({0.0: 0.5}))
    alone = costmap.map_costs()
    assert costmap.cost_at(1.025, 1.025) == LETHAL and alone.cost_at(1.025, 1.025) == FREE
    np.testing.assert_array_equal(alone.costs, full_recomposition_without_lidar(costmap))
    assert not alone.costs.flags.writeable
    assert costmap.cost_at(1.025, 1.025) == LETHAL  # the live costs are left as they were


def full_recomposition_without_lidar(costmap: Costmap) -> npt.NDArray[np.uint8]:
    info = costmap.info
    master = np.full((info.height, info.width), FREE, dtype=np.uint8)
    for layer in costmap.layers:
        if type(layer).__name__ != "ObstacleLayer":
            layer.update_costs(master, win.full(info.width, info.height))
    return master


def test_an_obstacle_that_moved_is_cleared_by_the_next_scan_through_it() -> None:
    costmap = Costmap.from_map(free_map(), BARE)
    costmap.update_scan(ROBOT, scan({0.0: 1.0}))
    assert costmap.costs[20, 30] == LETHAL
    costmap.update_scan(ROBOT, scan({0.0: 1.5}))
    assert costmap.costs[20, 30] == FREE
    assert costmap.costs[20, 35] == LETHAL


def test_beam_without_return_clears_up_to_the_raytrace_range() -> None:
    config = CostmapConfig(robot_radius=0.0, inflation_radius=0.0, raytrace_max_range=1.2)
    costmap = Costmap.from_map(free_map(), config)
    costmap.update_scan(ROBOT, scan({0.0: 1.0}))
    costmap.update_scan(Pose2D(0.55, 2.05, 0.0), scan({0.0: 3.0}))  # mark (35, 20) from afar
    assert costmap.costs[20, 30] == LETHAL and costmap.costs[20, 35] == LETHAL
    costmap.update_scan(ROBOT, scan({0.0: math.inf}))
    assert costmap.costs[20, 30] == FREE  # 1.0 m: within the raytrace range
    assert costmap.costs[20, 35] == LETHAL  # 1.5 m: beyond it


@pytest.mark.parametrize(
    "bad", [math.nan, 0.01, -1.0, 25.0], ids=["nan", "below-min", "neg", "above-max"]
)
def test_invalid_ranges_mark_nothing_and_clear_like_no_return(bad: float) -> None:
    costmap = Costmap.from_map(free_map(), BARE)
    costmap.update_scan(ROBOT, scan({0.0: 1.0}))
    costmap.update_scan(ROBOT, scan({0.0: bad}))
    assert (costmap.costs == FREE).all()


def test_no_return_clears_no_farther_than_the_sensor_range() -> None:
    costmap = Costmap.from_map(free_map(), BARE)
    costmap.update_scan(ROBOT, scan({0.0: 1.0}))
    costmap.update_scan(ROBOT, scan({0.0: math.inf}, range_max=0.8))
    assert costmap.costs[20, 30] == LETHAL


def test_return_beyond_obstacle_range_clears_but_does_not_mark() -> None:
    config = CostmapConfig(robot_radius=0.0, inflation_radius=0.0, obstacle_max_range=0.9)
    costmap = Costmap.from_map(free_map(), config)
    costmap.update_scan(Pose2D(1.55, 2.05, 0.0), scan({0.0: 1.5}))  # hits (30, 20) at 1.5 m
    assert costmap.costs[20, 30] == FREE
    costmap.update_scan(Pose2D(2.55, 2.05, 0.0), scan({0.0: 0.5}))  # marks (30, 20)
    assert costmap.costs[20, 30] == LETHAL
    costmap.update_scan(ROBOT, scan({0.0: 1.5}))  # passes through (30, 20), hit too far to mark
    assert costmap.costs[20, 30] == FREE and costmap.costs[20, 35] == FREE


def test_scan_on_a_map_with_rotated_origin_marks_the_cell_holding_the_endpoint() -> None:
    grid = Map.from_occupied(
        np.zeros((20, 20), dtype=bool), resolution=0.1, origin=Pose2D(1.0, 1.0, math.pi / 2)
    )
    costmap = Costmap.from_map(grid, BARE)
    x, y = grid.info.cell_to_world(5, 5)  # (0.45, 1.55): the grid's +x is the world's +y
    costmap.update_scan(Pose2D(x, y, 0.0), scan({0.0: 0.5}))
    assert costmap.cost_at(x + 0.5, y) == LETHAL
    assert costmap.costs[0, 5] == LETHAL
    assert np.count_nonzero(costmap.costs == LETHAL) == 1


def test_beams_are_turned_by_robot_heading_and_sensor_mount() -> None:
    costmap = Costmap.from_map(free_map(), BARE)
    mount = Pose2D(0.2, 0.0, math.pi / 2)  # 0.2 m ahead, looking left
    costmap.update_scan(Pose2D(2.05, 2.05, math.pi / 2), scan({0.0: 0.5}, sensor_pose=mount))
    # Robot faces +y, so the sensor sits at (2.05, 2.25) and looks along -x.
    assert costmap.cost_at(1.55, 2.25) == LETHAL
    assert np.count_nonzero(costmap.costs == LETHAL) == 1


@pytest.mark.parametrize("long_angle", [0.001, -0.001], ids=["hit-beam-first", "hit-beam-last"])
def test_marking_survives_other_beams_of_the_same_scan_passing_through(long_angle: float) -> None:
    costmap = Costmap.from_map(free_map(), BARE)
    # The long beam crosses the short beam's end cell (30, 20), before or after it in the scan.
    costmap.update_scan(ROBOT, scan({0.0: 1.0, long_angle: 1.8}))
    assert costmap.costs[20, 30] == LETHAL
    assert costmap.costs[20, 38] == LETHAL


def test_beams_never_clear_map_walls_or_keepouts() -> None:
    occupied = np.zeros((41, 41), dtype=bool)
    occupied[20, 25] = True
    costmap = Costmap.from_map(Map.from_occupied(occupied, resolution=0.1), BARE)
    costmap.set_keepouts([CircleZone(x=2.75, y=2.05, radius=0.01)])
    costmap.update_scan(ROBOT, scan({0.0: 1.5}))  # a scan that "sees through" both
    assert costmap.costs[20, 25] == LETHAL and costmap.costs[20, 27] == LETHAL
    assert costmap.costs[20, 26] == FREE


def test_beams_reveal_unknown_map_cells_as_free_when_unknown_is_tracked() -> None:
    config = CostmapConfig(robot_radius=0.0, inflation_radius=0.0, track_unknown=True)
    costmap = Costmap.from_map(map_from_ascii("." * 10 + "?" * 10, resolution=0.1), config)
    costmap.update_scan(Pose2D(0.05, 0.05, 0.0), scan({0.0: 1.5}))
    assert costmap.costs[0].tolist() == [0] * 15 + [LETHAL] + [UNKNOWN] * 4


def test_clear_obstacles_restores_the_costs_of_the_map_alone() -> None:
    costmap = Costmap.from_map(free_map(resolution=0.05), CostmapConfig())
    before = costmap.costs.copy()
    costmap.update_scan(ROBOT, scan({0.0: 0.5, 1.0: 0.7, -2.0: 0.3}))
    assert not np.array_equal(costmap.costs, before)
    costmap.clear_obstacles()
    np.testing.assert_array_equal(costmap.costs, before)


def test_scan_does_nothing_when_the_obstacle_layer_is_off() -> None:
    costmap = Costmap.from_map(free_map(), CostmapConfig(obstacle_layer=False))
    costmap.update_scan(ROBOT, scan({0.0: 1.0}))
    assert (costmap.costs == FREE).all()
    costmap.clear_obstacles()
    assert (costmap.costs == FREE).all()


# --- incremental recomposition ---------------------------------------------------------------


class StampLayer:
    """Raises every cell of each window it is asked to redraw to its call count."""

    def __init__(self) -> None:
        self.windows: list[Window] = []

    def update_bounds(self, pose: Pose2D, window: Window | None) -> Window | None:
        return window

    def update_costs(self, master: npt.NDArray[np.uint8], window: Window) -> None:
        self.windows.append(window)
        region = master[win.slices(window)]
        np.maximum(region, len(self.windows), out=region)


def test_scan_on_one_side_recomposes_only_its_window() -> None:
    stamp = StampLayer()
    config = CostmapConfig(obstacle_max_range=2.0, raytrace_max_range=2.0)
    costmap = Costmap(free_map(width=400, height=40, resolution=0.05), config, extra_layers=[stamp])
    assert stamp.windows == [(0, 0, 400, 40)]
    costmap.update_scan(Pose2D(1.0, 1.0, 0.0), scan({-0.5: 1.0, 0.0: 1.2, 0.5: 1.0}))
    assert len(stamp.windows) == 2
    ix0, iy0, ix1, iy1 = stamp.windows[1]
    # The beams clear up to x = 3.0 m (cell 60) at most; inflation adds 11 cells on both sides.
    assert ix0 == 20 - 11 and 60 <= ix1 <= 61 + 11
    assert costmap.last_window == stamp.windows[1]
    assert (costmap.costs[:, ix1:] == 1).all()  # not redrawn since construction
    assert (costmap.costs[:, :ix0] == 1).all()
    assert np.count_nonzero(costmap.costs[iy0:iy1, ix0:ix1] == 2) > 0


def test_robot_standing_still_in_a_static_scene_redraws_nothing() -> None:
    costmap = Costmap.from_map(free_map(), CostmapConfig())
    beams = {0.0: 1.0, 0.3: 1.2, 1.5: 0.6}
    costmap.update_scan(ROBOT, scan(beams))
    assert costmap.last_window is not None
    costmap.update_scan(ROBOT, scan(beams))
    assert costmap.last_window is None


def test_incremental_updates_equal_a_full_recomposition() -> None:
    rng = np.random.default_rng(7)
    walls = np.zeros((80, 120), dtype=bool)
    walls[0, :] = walls[-1, :] = walls[:, 0] = walls[:, -1] = True
    walls[40, 10:70] = True
    grid = Map.from_occupied(walls, resolution=0.05, origin=Pose2D(-1.0, 0.5, 0.0))
    config = CostmapConfig(track_unknown=False, obstacle_max_range=2.5, raytrace_max_range=3.0)
    costmap = Costmap.from_map(grid, config)
    costmap.set_keepouts([VirtualWall(points=((1.0, 1.0), (2.0, 2.5)), thickness=0.1)])
    angles = np.linspace(-math.pi, math.pi, 90, endpoint=False)
    for _ in range(25):
        world = walls.copy()
        for _ in range(3):  # people who move between scans
            cx, cy = rng.integers(5, 115), rng.integers(5, 75)
            world[cy - 2 : cy + 2, cx - 2 : cx + 2] = True
        ix, iy = rng.integers(3, 117), rng.integers(3, 77)
        if world[iy, ix]:
            continue
        x, y = grid.info.cell_to_world(int(ix), int(iy))
        pose = Pose2D(x, y, float(rng.uniform(-math.pi, math.pi)))
        ranges = cast_rays(world, grid.info, x, y, angles + pose.theta, 4.0)
        ranges[rng.random(angles.shape[0]) < 0.1] = np.nan
        costmap.update_scan(
            pose,
            LaserScan(0.0, -math.pi, angles[1] - angles[0], 0.05, 4.0, ranges.astype(np.float32)),
        )
        np.testing.assert_array_equal(costmap.costs, full_recomposition(costmap))
    costmap.clear_obstacles()
    np.testing.assert_array_equal(costmap.costs, full_recomposition(costmap))


# --- map swap --------------------------------------------------------------------------------


def test_map_swap_with_same_geometry_redraws_only_the_changed_cells() -> None:
    costmap = Costmap.from_map(free_map(width=100, height=100, resolution=0.05), CostmapConfig())
    occupied = np.zeros((100, 100), dtype=bool)
    occupied[50, 50] = True
    costmap.set_static_map(Map.from_occupied(occupied, resolution=0.05))
    assert costmap.last_window == (50 - 11, 50 - 11, 51 + 11, 51 + 11)
    np.testing.assert_array_equal(costmap.costs, single_obstacle_like(occupied))


def single_obstacle_like(occupied: npt.NDArray[np.bool_]) -> npt.NDArray[np.uint8]:
    return Costmap.from_map(Map.from_occupied(occupied, resolution=0.05), CostmapConfig()).costs


def test_map_swap_forgets_obstacles_and_keeps_keepouts() -> None:
    costmap = Costmap.from_map(free_map(), BARE)
    costmap.set_keepouts([CircleZone(x=0.55, y=0.55, radius=0.01)])
    costmap.update_scan(ROBOT, scan({0.0: 1.0}))
    costmap.set_static_map(free_map())
    assert costmap.cost_at(3.05, 2.05) == FREE
    assert costmap.cost_at(0.55, 0.55) == LETHAL
    bigger = free_map(width=60, height=30, resolution=0.05)
    costmap.set_static_map(bigger)
    assert costmap.info == bigger.info and costmap.costs.shape == (30, 60)
    assert costmap.cost_at(0.55, 0.55) == LETHAL
    assert np.count_nonzero(costmap.costs == LETHAL) == 1


def test_map_swap_to_another_geometry_is_refused_with_extra_layers() -> None:
    costmap = Costmap(free_map(), BARE, extra_layers=[StampLayer()])
    with pytest.raises(InvalidRequest):
        costmap.set_static_map(free_map(width=10))


# --- reading ---------------------------------------------------------------------------------


def test_cost_at_reads_the_cell_and_is_lethal_outside_the_map() -> None:
    grid = map_from_ascii("..#", resolution=0.5, origin=Pose2D(-1.0, 0.0, 0.0))
    costmap = Costmap.from_map(grid, BARE)
    assert costmap.cost_at(0.2, 0.2) == LETHAL
    assert costmap.cost_at(-0.9, 0.4) == FREE
    assert costmap.cost_at(-1.01, 0.2) == LETHAL
    assert costmap.cost_at(0.0, 0.6) == LETHAL


def test_snapshot_is_a_frozen_copy_unaffected_by_later_updates() -> None:
    costmap = Costmap.from_map(free_map(), CostmapConfig())
    snap = costmap.snapshot()
    costmap.update_scan(ROBOT, scan({0.0: 1.0}))
    assert costmap.costs[20, 30] == LETHAL
    assert snap.costs[20, 30] == FREE and snap.cost_at(3.05, 2.05) == FREE
    assert (snap.costs == FREE).all()
    with pytest.raises(ValueError):
        snap.costs[0, 0] = LETHAL
    grid: CostGrid = snap
    assert isinstance(snap, CostSnapshot) and grid.info == costmap.info


def test_live_costs_are_read_only_to_callers() -> None:
    costmap = Costmap.from_map(free_map(), CostmapConfig())
    with pytest.raises(ValueError):
        costmap.costs[0, 0] = LETHAL
