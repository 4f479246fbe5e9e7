"""Global relocalization on the demo floors from one simulated scan, with no prior: found within
0.1 m / 0.05 rad, or reported as a failure, never a wrong pose; a featureless hall is ambiguous."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import ndimage

from polynav.errors import ConfigError
from polynav.geometry import Pose2D, angle_diff
from polynav.mapping.relocalization import RelocalizationConfig, Relocalizer
from polynav.maps.map import Map, MapInfo
from polynav.robot.sim.simulation import Simulation
from polynav.worlds import load_world
from polynav.worlds.world import World, WorldFloor

WORLD = load_world("demo")


def _random_poses(floor: WorldFloor, count: int, seed: int) -> list[Pose2D]:
    info = floor.map.info
    clear = ndimage.distance_transform_edt(floor.map.data == 0) * info.resolution
    cells = np.argwhere(clear >= 0.45)
    rng = np.random.default_rng(seed)
    poses = []
    for _ in range(count):
        iy, ix = cells[rng.integers(len(cells))]
        x, y = info.cell_to_world(int(ix), int(iy))
        poses.append(Pose2D(x, y, float(rng.uniform(-math.pi, math.pi))))
    return poses


def _scan_at(world: World, floor: str, pose: Pose2D, seed: int):  # noqa: ANN202
    sim = Simulation(world, seed=seed, floor=floor, pose=pose, people=False)
    for _ in range(4):
        sim.step()
    assert sim.scan is not None
    return sim.scan, sim.true_pose


@pytest.mark.parametrize("floor_name", ["floor1", "floor2"])
def test_twenty_random_poses_are_found_or_refused_never_wrong(floor_name: str) -> None:
    floor = WORLD.floor(floor_name)
    relocalizer = Relocalizer(floor.map)
    found = 0
    for k, pose in enumerate(_random_poses(floor, 20, seed=11)):
        scan, true = _scan_at(WORLD, floor_name, pose, seed=k)
        result = relocalizer.locate(scan)
        if result.pose is None:
            assert result.reason in ("ambiguous", "no match")
            continue
        found += 1
        assert result.pose.distance_to(true) <= 0.1, (k, result, true)
        assert abs(angle_diff(result.pose.theta, true.theta)) <= 0.05, (k, result, true)
        assert result.score - result.runner_up >= relocalizer.config.margin
    # floor 2's guest rooms are identical: from inside one, "ambiguous" is the right answer.
    assert found >= (15 if floor_name == "floor1" else 4)


def test_a_map_with_a_rotated_origin_answers_in_its_own_frame() -> None:
    floor = WORLD.floor("floor1")
    info = floor.map.info
    turned = Pose2D(3.0, -2.0, 0.7)
    rotated = Map(MapInfo(info.resolution, info.width, info.height, turned), floor.map.data)
    relocalizer = Relocalizer(rotated)
    found = 0
    for k, pose in enumerate(_random_poses(floor, 5, seed=4)):
        scan, true = _scan_at(WORLD, "floor1", pose, seed=k)
        result = relocalizer.locate(scan)
        if result.pose is None:
            continue
        found += 1
        expected = turned.compose(info.origin.inverse().compose(true))
        assert result.pose.distance_to(expected) <= 0.1, (k, result, expected)
        assert abs(angle_diff(result.pose.theta, expected.theta)) <= 0.05, (k, result, expected)
    assert found >= 3


def _hall(size: float = 16.0) -> Map:
    res = 0.05
    n = int(size / res)
    data = np.zeros((n, n), dtype=np.int8)
    data[:2, :] = data[-2:, :] = data[:, :2] = data[:, -2:] = 100
    return Map(MapInfo(res, n, n, Pose2D()), data)


def test_a_featureless_hall_is_ambiguous_or_no_match_never_a_pose() -> None:
    hall = _hall()
    floor = WorldFloor("hall", 1, "hall", hall, (), None, ())
    world = World("hall", (floor,), "hall", Pose2D(8.0, 8.0, 0.0))
    relocalizer = Relocalizer(hall)
    for k, pose in enumerate([Pose2D(8.0, 8.0, 0.3), Pose2D(3.0, 8.0, 2.0)]):
        scan, _ = _scan_at(world, "hall", pose, seed=k)
        assert np.isfinite(scan.ranges).sum() > 100  # it sees the walls
        result = relocalizer.locate(scan)
        assert result.pose is None and result.reason in ("ambiguous", "no match"), result


def test_config_rejects_bad_values() -> None:
    for bad in ({"sigma": 0.0}, {"depth": 0}, {"points": 5}, {"min_score": 1.5},
                {"theta_step": math.inf}):
        with pytest.raises(ConfigError):
            RelocalizationConfig(**bad)  # type: ignore[arg-type]
