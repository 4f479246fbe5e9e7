from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.geometry import Pose2D
from polynav.maps.ascii import map_from_ascii
from polynav.robot.sim.config import SimConfig
from polynav.robot.sim.lidar import Lidar, circle_ranges

# 5 m x 3 m outside; the free interior spans x 0.5..4.5, y 0.5..2.5.
ROOM = map_from_ascii(
    """
    ##########
    #........#
    #........#
    #........#
    #........#
    ##########
    """,
    resolution=0.5,
)
NO_PEOPLE = np.empty((0, 3))


def _lidar(seed: int = 0, **changes: float) -> Lidar:
    config = SimConfig(**{"lidar_beams": 4, "lidar_range_noise": 0.0, **changes})  # type: ignore[arg-type]
    return Lidar(config, np.random.default_rng(seed))


def test_full_circle_beams_start_at_minus_pi_and_stop_short_of_pi() -> None:
    scan = Lidar(SimConfig(), np.random.default_rng(0)).scan(
        ROOM.occupied(), ROOM.info, Pose2D(2.0, 1.25, 0.0), NO_PEOPLE, 0.0)
    assert scan.ranges.shape == (360,) and scan.ranges.dtype == np.float32
    assert scan.angle_min == -math.pi
    assert scan.angle_increment == pytest.approx(2 * math.pi / 360)
    assert scan.angles[-1] == pytest.approx(math.pi - 2 * math.pi / 360)
    assert (scan.range_min, scan.range_max) == (0.05, 12.0)


def test_partial_field_of_view_has_beams_on_both_edges() -> None:
    lidar = _lidar(lidar_beams=5, lidar_fov=math.pi)
    scan = lidar.scan(ROOM.occupied(), ROOM.info, Pose2D(2.0, 1.25, 0.0), NO_PEOPLE, 0.0)
    assert scan.angles == pytest.approx([-math.pi / 2, -math.pi / 4, 0.0, math.pi / 4,
                                         math.pi / 2])


def test_ranges_equal_the_distances_to_the_walls() -> None:
    scan = _lidar().scan(ROOM.occupied(), ROOM.info, Pose2D(2.0, 1.25, 0.0), NO_PEOPLE, 3.5)
    # Beams at -pi (west), -pi/2 (south), 0 (east), pi/2 (north).
    assert scan.ranges == pytest.approx([1.5, 0.75, 2.5, 1.25])
    assert scan.stamp == 3.5


def test_ranges_turn_with_the_robot() -> None:
    scan = _lidar().scan(ROOM.occupied(), ROOM.info, Pose2D(2.0, 1.25, math.pi / 2), NO_PEOPLE,
                         0.0)
    # Facing north, the beams at -pi, -pi/2, 0, pi/2 look south, east, north and west.
    assert scan.ranges == pytest.approx([0.75, 2.5, 1.25, 1.5])


def test_a_person_in_front_shortens_the_beam_to_their_near_side() -> None:
    person = np.array([[3.5, 1.25, 0.25]])
    scan = _lidar().scan(ROOM.occupied(), ROOM.info, Pose2D(2.0, 1.25, 0.0), person, 0.0)
    assert scan.ranges == pytest.approx([1.5, 0.75, 1.25, 1.25])


def test_circle_ranges_hit_off_centre_and_miss_beside() -> None:
    angles = np.array([math.atan2(0.1, 2.0), math.pi / 2, 0.0])
    ranges = circle_ranges(0.0, 0.0, angles, np.array([[2.0, 0.0, 0.3]]), 10.0)
    # Beam through (2, 0.1) direction: nearer root of |t u - c|² = r².
    u = np.array([math.cos(angles[0]), math.sin(angles[0])])
    along = u @ np.array([2.0, 0.0])
    expected = along - math.sqrt(along**2 - (4.0 - 0.09))
    assert ranges[0] == pytest.approx(expected)
    assert math.isinf(ranges[1])
    assert ranges[2] == pytest.approx(1.7)


def test_returns_beyond_range_are_infinite() -> None:
    scan = _lidar(lidar_range=1.3).scan(ROOM.occupied(), ROOM.info, Pose2D(2.0, 1.25, 0.0),
                                        NO_PEOPLE, 0.0)
    assert np.isinf(scan.ranges[[0, 2]]).all()
    assert scan.ranges[[1, 3]] == pytest.approx([0.75, 1.25])


def test_noise_is_unbiased_with_the_configured_spread() -> None:
    config = SimConfig(lidar_range_noise=0.01)
    exact = Lidar(SimConfig(lidar_range_noise=0.0), np.random.default_rng(0))
    noisy = Lidar(config, np.random.default_rng(7))
    pose = Pose2D(2.0, 1.25, 0.3)
    truth = exact.scan(ROOM.occupied(), ROOM.info, pose, NO_PEOPLE, 0.0).ranges.astype(float)
    errors = np.concatenate([
        noisy.scan(ROOM.occupied(), ROOM.info, pose, NO_PEOPLE, 0.0).ranges - truth
        for _ in range(20)
    ])
    assert errors.size == 7200
    assert abs(errors.mean()) < 0.001
    assert 0.0095 < errors.std() < 0.0105


def test_same_seed_gives_identical_scans_and_another_seed_differs() -> None:
    pose = Pose2D(2.0, 1.25, 0.3)

    def scans(seed: int) -> list[np.ndarray]:
        lidar = Lidar(SimConfig(), np.random.default_rng(seed))
        return [lidar.scan(ROOM.occupied(), ROOM.info, pose, NO_PEOPLE, 0.0).ranges
                for _ in range(3)]

    first, again, other = scans(1), scans(1), scans(2)
    assert all(np.array_equal(a, b) for a, b in zip(first, again, strict=True))
    assert not np.array_equal(first[0], other[0])
    assert not np.array_equal(first[0], first[1])
