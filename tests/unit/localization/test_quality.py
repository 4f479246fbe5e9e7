"""The quality figure against scans that do not fit: a shuffled scan (every range real, every
bearing wrong) must read as low quality, never move the pose, and end in LOST on ``now``."""

from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.geometry import Pose2D, Twist
from polynav.localization.interface import LocalizationState
from polynav.localization.likelihood_field import build_likelihood_field
from polynav.localization.pose_tracker import PoseTracker, PoseTrackerConfig, warm_up
from polynav.localization.scan_matcher import ScanMatcher, SearchWindow, scan_points
from polynav.maps.map import Map
from polynav.maps.raycast import cast_rays
from polynav.robot.interface import LaserScan, Odometry

RES = 0.05
ANGLES = -math.pi + (2.0 * math.pi / 360) * np.arange(360)
POSES = [Pose2D(3.0, 2.0, 0.3), Pose2D(6.0, 2.5, -1.0), Pose2D(1.5, 4.5, 2.0)]


def _office() -> Map:
    """An 8 m x 6 m floor: a partition, an office corner, a table block and a pillar."""
    occ = np.zeros((120, 160), dtype=bool)
    occ[:2, :] = occ[-2:, :] = occ[:, :2] = occ[:, -2:] = True
    occ[60:62, 2:50] = True
    occ[80:120, 100:102] = True
    occ[80:82, 120:160] = True
    occ[20:36, 70:90] = True
    occ[30:34, 130:134] = True
    return Map.from_occupied(occ, resolution=RES)


def _ranges(grid: Map, pose: Pose2D, rng: np.random.Generator) -> np.ndarray:
    ranges = cast_rays(grid.occupied(), grid.info, pose.x, pose.y, ANGLES + pose.theta, 10.0)
    return ranges + 0.01 * rng.standard_normal(ranges.shape[0])


@pytest.mark.parametrize("seed", range(len(POSES)))
def test_quality_is_full_at_the_true_pose_and_low_for_a_shuffled_scan(seed):
    grid = _office()
    true = POSES[seed]
    rng = np.random.default_rng(seed)
    ranges = _ranges(grid, true, rng)
    kwargs = {"range_min": 0.05, "range_max": 10.0, "sensor_pose": Pose2D(), "step": 4}
    points = scan_points(ranges, ANGLES, **kwargs)
    shuffled = scan_points(rng.permutation(ranges), ANGLES, **kwargs)
    matcher = ScanMatcher(build_likelihood_field(grid))
    window = SearchWindow(0.15, math.radians(6.0), math.radians(0.5))

    assert matcher.evaluate(points, true).inliers == 1.0
    assert matcher.match(points, true, window).inliers == 1.0
    # Even the best pose of the tracking window fits a shuffled scan badly (measured 0.14 to
    # 0.27 on these poses), below the default lost_quality.
    assert matcher.match(shuffled, true, window).inliers < PoseTrackerConfig().lost_quality


def test_shuffled_scans_hold_the_pose_end_in_lost_and_good_scans_recover():
    warm_up()
    grid = _office()
    true = POSES[0]
    config = PoseTrackerConfig()
    tracker = PoseTracker(config)
    tracker.set_map(grid)
    tracker.initialize(true, 0.0)
    rng = np.random.default_rng(11)
    odometry = Odometry(0.0, Pose2D(), Twist())  # standing still

    def feed(start: int, stop: int, shuffle: bool) -> list[tuple[float, float, object, Pose2D]]:
        out = []
        for k in range(start, stop):
            now = 0.05 * k  # 20 Hz updates; a scan every third one (about 15 Hz)
            scan = None
            if k % 3 == 0:
                ranges = _ranges(grid, true, rng)
                if shuffle:
                    ranges = rng.permutation(ranges)
                scan = LaserScan(now, float(ANGLES[0]), 2.0 * math.pi / 360, 0.05, 10.0,
                                 ranges.astype(np.float32))
            odom = Odometry(now, odometry.pose, odometry.twist)
            estimate = tracker.update(odom, None, scan, now)
            out.append((now, estimate.quality, estimate.state, estimate.pose))
        return out

    good = feed(0, 20, shuffle=False)
    assert {state for _, _, state, _ in good} == {LocalizationState.TRACKING}
    assert min(q for _, q, _, _ in good) == 1.0

    bad = feed(20, 120, shuffle=True)
    low = [now for now, q, _, _ in bad if q < config.lost_quality]
    lost = [now for now, _, state, _ in bad if state is LocalizationState.LOST]
    assert low and lost
    assert lost[0] == pytest.approx(low[0] + config.lost_after)
    assert all(state is LocalizationState.TRACKING for now, _, state, _ in bad if now < lost[0])
    # Bad matches are not applied: the pose stays where it was.
    assert max(pose.distance_to(true) for _, _, _, pose in bad) < 0.01

    back = feed(120, 140, shuffle=False)
    assert back[-1][2] is LocalizationState.TRACKING
    assert back[-1][3].distance_to(true) < 0.01
