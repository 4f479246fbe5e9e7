from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.geometry import Pose2D, angle_diff
from polynav.localization import scan_matcher
from polynav.localization.likelihood_field import build_likelihood_field
from polynav.localization.scan_matcher import ScanMatcher, SearchWindow, scan_points
from polynav.maps.map import Map
from polynav.maps.raycast import cast_rays

RES = 0.05
ANGLES = -math.pi + (2.0 * math.pi / 360) * np.arange(360)


def _room() -> Map:
    """A 6 m x 4 m room with an alcove and two boxes, so no pose looks like another."""
    occ = np.zeros((80, 120), dtype=bool)
    occ[:2, :] = occ[-2:, :] = occ[:, :2] = occ[:, -2:] = True
    occ[50:52, 40:70] = True  # a shelf
    occ[10:22, 90:100] = True  # a box
    occ[60:78, 20:22] = True  # a partition
    return Map.from_occupied(occ, resolution=RES, origin=Pose2D(-1.0, 0.5))


def _scan(grid: Map, pose: Pose2D, *, noise: float = 0.0, seed: int = 0) -> np.ndarray:
    ranges = cast_rays(grid.occupied(), grid.info, pose.x, pose.y, ANGLES + pose.theta, 10.0)
    if noise:
        ranges = ranges + noise * np.random.default_rng(seed).standard_normal(ranges.shape[0])
    return ranges


def test_matcher_recovers_known_offset_within_a_cell():
    grid = _room()
    true = Pose2D(1.52, 1.93, 0.1)
    pts = scan_points(_scan(grid, true), ANGLES, range_min=0.05, range_max=10.0,
                      sensor_pose=Pose2D(), step=3)
    matcher = ScanMatcher(build_likelihood_field(grid))
    guess = Pose2D(true.x + 0.11, true.y - 0.08, true.theta + math.radians(4.0))
    window = SearchWindow(0.15, math.radians(6.0), math.radians(0.5))

    grid_only = matcher.match(pts, guess, window, refine=False)
    refined = matcher.match(pts, guess, window)

    assert grid_only.pose.distance_to(true) < RES
    assert abs(angle_diff(grid_only.pose.theta, true.theta)) <= math.radians(0.5)
    assert refined.pose.distance_to(true) < 0.2 * RES
    assert abs(angle_diff(refined.pose.theta, true.theta)) < math.radians(0.2)
    assert refined.inliers == 1.0
    assert refined.points == 120


def test_wide_coarse_search_recovers_one_metre_and_thirty_degrees():
    grid = _room()
    true = Pose2D(2.0, 2.6, -0.4)
    pts = scan_points(_scan(grid, true, noise=0.01), ANGLES, range_min=0.05, range_max=10.0,
                      sensor_pose=Pose2D(), step=2)
    matcher = ScanMatcher(build_likelihood_field(grid))
    guess = Pose2D(true.x - 0.7, true.y + 0.7, true.theta + math.radians(28.0))
    window = SearchWindow(1.0, math.radians(30.0), math.radians(0.5), coarse=True)

    found = matcher.match(pts, guess, window)

    assert found.pose.distance_to(true) < 0.02
    assert abs(angle_diff(found.pose.theta, true.theta)) < math.radians(0.5)
    assert found.inliers > 0.95


def test_prior_keeps_corridor_match_where_odometry_put_it():
    # An endless corridor: along x, every pose fits; the prior keeps the guess.
    occ = np.zeros((40, 400), dtype=bool)
    occ[:2, :] = occ[-2:, :] = True
    grid = Map.from_occupied(occ, resolution=RES)
    true = Pose2D(10.0, 1.0, 0.0)
    pts = scan_points(_scan(grid, true), ANGLES, range_min=0.05, range_max=10.0,
                      sensor_pose=Pose2D(), step=4)
    matcher = ScanMatcher(build_likelihood_field(grid))
    guess = Pose2D(10.07, 1.04, 0.0)

    found = matcher.match(pts, guess, SearchWindow(0.15, 0.1, math.radians(0.5)),
                          prior_xy=0.5, prior_theta=0.5)

    assert found.pose.x == pytest.approx(10.07, abs=0.002)
    assert found.pose.y == pytest.approx(1.0, abs=0.005)


def test_matcher_works_on_a_map_with_rotated_origin():
    grid = _room()
    field = build_likelihood_field(grid)
    true = Pose2D(1.52, 1.93, 0.1)
    pts = scan_points(_scan(grid, true), ANGLES, range_min=0.05, range_max=10.0,
                      sensor_pose=Pose2D(), step=3)
    # The same grid placed in a world rotated by 0.5 rad about the world origin.
    turn = Pose2D(0.0, 0.0, 0.5)
    rotated = Map(type(grid.info)(RES, grid.info.width, grid.info.height,
                                  turn.compose(grid.info.origin)), grid.data)
    matcher = ScanMatcher(build_likelihood_field(rotated))
    true_rotated = turn.compose(true)
    guess = true_rotated.compose(Pose2D(0.08, 0.05, 0.05))

    found = matcher.match(pts, guess, SearchWindow(0.15, math.radians(6.0),
                                                   math.radians(0.5)))

    assert field.info.origin.theta == 0.0
    assert found.pose.distance_to(true_rotated) < 0.01
    assert abs(angle_diff(found.pose.theta, true_rotated.theta)) < math.radians(0.2)


def test_evaluate_counts_inliers_at_a_pose():
    grid = _room()
    matcher = ScanMatcher(build_likelihood_field(grid))
    true = Pose2D(1.52, 1.93, 0.1)
    pts = scan_points(_scan(grid, true), ANGLES, range_min=0.05, range_max=10.0,
                      sensor_pose=Pose2D(), step=3)
    assert matcher.evaluate(pts, true).inliers == 1.0
    assert matcher.evaluate(pts, true.compose(Pose2D(0.5, 0.0, 0.3))).inliers < 0.5


def test_scan_points_skip_missing_returns_and_apply_the_mount():
    ranges = np.array([1.0, np.inf, 2.0, 0.01, np.nan, 3.0], dtype=np.float32)
    angles = np.array([0.0, 0.1, math.pi / 2, 0.3, 0.4, math.pi])
    mount = Pose2D(0.2, 0.0, math.pi / 2)

    pts = scan_points(ranges, angles, range_min=0.05, range_max=12.0, sensor_pose=mount)

    assert pts == pytest.approx(np.array([[0.2, 1.0], [-1.8, 0.0], [0.2, -3.0]]), abs=1e-9)
    every_other = scan_points(ranges, angles, range_min=0.05, range_max=12.0,
                              sensor_pose=Pose2D(), step=2)
    assert every_other == pytest.approx(np.array([[1.0, 0.0], [0.0, 2.0]]), abs=1e-9)


def test_empty_scan_returns_the_guess_with_zero_score():
    matcher = ScanMatcher(build_likelihood_field(_room()))
    guess = Pose2D(1.0, 1.0, 0.2)
    found = matcher.match(np.empty((0, 2)), guess, SearchWindow(0.1, 0.1, 0.01))
    assert found.pose == guess
    assert (found.score, found.inliers, found.points) == (0.0, 0.0, 0)


def test_warm_up_runs():
    scan_matcher.warm_up()
