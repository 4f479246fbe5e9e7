from __future__ import annotations

import numpy as np

from polynav.geometry import Pose2D
from polynav.robot.interface import LaserScan
from polynav.runtime.site_queries import resample, scan_points


def test_resample_keeps_short_paths_and_spaces_long_ones_evenly() -> None:
    short = np.array([[0.0, 0.0], [1.0, 0.0]])
    assert resample(short, 5) is short
    line = np.column_stack([np.linspace(0.0, 10.0, 5001), np.zeros(5001)])
    out = resample(line, 2000)
    assert out.shape == (2000, 2)
    assert np.allclose(out[[0, -1]], line[[0, -1]])
    steps = np.diff(out[:, 0])
    assert np.allclose(steps, 10.0 / 1999)


def test_scan_points_are_placed_in_the_map_from_the_robot_pose() -> None:
    scan = LaserScan(
        stamp=0.0, angle_min=0.0, angle_increment=np.pi / 2, range_min=0.1, range_max=5.0,
        ranges=np.array([1.0, np.inf, 2.0, 0.05], dtype=np.float32),
    )
    points = scan_points(scan, Pose2D(1.0, 1.0, np.pi / 2))
    # Beam 0 (ahead, +y in the map) hits 1 m away, beam 2 (behind) 2 m; the others are no
    # return and too near.
    assert np.allclose(points, [[1.0, 2.0], [1.0, -1.0]])
