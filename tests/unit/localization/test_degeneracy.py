"""The degeneracy measure: which directions of the pose a scan match pins, read from the match's
Gauss-Newton normal matrix, and a tracker that corrects only those."""

from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.geometry import Pose2D, Twist, angle_diff
from polynav.localization import degeneracy
from polynav.localization.interface import LocalizationState
from polynav.localization.likelihood_field import build_likelihood_field
from polynav.localization.pose_tracker import PoseTracker, PoseTrackerConfig, warm_up
from polynav.localization.scan_matcher import ScanMatcher, SearchWindow, scan_points
from polynav.maps.map import Map
from polynav.maps.raycast import cast_rays
from polynav.robot.interface import ImuReading, LaserScan, Odometry

RES = 0.05
RANGE = 12.0
ANGLES = -math.pi + (2.0 * math.pi / 360) * np.arange(360)
CONFIG = PoseTrackerConfig()


def _corridor() -> Map:
    """A 50 m x 1 m corridor along x, closed at both ends by 0.1 m walls."""
    occ = np.ones((24, 1004), dtype=bool)
    occ[2:22, 2:1002] = False
    return Map.from_occupied(occ, resolution=RES)


def _room() -> Map:
    """A 6 m x 4 m empty room."""
    occ = np.zeros((80, 120), dtype=bool)
    occ[:2, :] = occ[-2:, :] = occ[:, :2] = occ[:, -2:] = True
    return Map.from_occupied(occ, resolution=RES)


def _hall() -> Map:
    """A 40 m x 40 m empty hall: from its middle no wall is within lidar range."""
    occ = np.zeros((800, 800), dtype=bool)
    occ[:2, :] = occ[-2:, :] = occ[:, :2] = occ[:, -2:] = True
    return Map.from_occupied(occ, resolution=RES)


def _ranges(grid: Map, pose: Pose2D, seed: int = 0) -> np.ndarray:
    ranges = cast_rays(grid.occupied(), grid.info, pose.x, pose.y, ANGLES + pose.theta, RANGE)
    return ranges + 0.01 * np.random.default_rng(seed).standard_normal(ranges.shape[0])


def _constraint(grid: Map, pose: Pose2D) -> degeneracy.Constraint:
    points = scan_points(_ranges(grid, pose), ANGLES, range_min=0.05, range_max=RANGE,
                         sensor_pose=Pose2D(), step=CONFIG.beam_step)
    matcher = ScanMatcher(build_likelihood_field(grid))
    match = matcher.match(points, pose, SearchWindow(0.15, math.radians(6.0),
                                                     math.radians(0.5)))
    information = matcher.information(points, match.pose,
                                      max_distance=CONFIG.constraint_distance)
    return degeneracy.constraint(information, length_scale=CONFIG.heading_length_scale,
                                 min_information=CONFIG.min_information)


@pytest.mark.parametrize("heading", [0.0, 0.7, -2.5])
def test_in_a_corridor_only_the_along_corridor_direction_is_unconstrained(heading):
    con = _constraint(_corridor(), Pose2D(25.0, 0.6, heading))

    assert con.degenerate
    (free,) = con.unconstrained_directions()
    assert abs(free[0]) > 0.99  # along x, the corridor's axis
    assert con.fraction_constrained(np.array([1.0, 0.0, 0.0])) < 0.01
    assert con.fraction_constrained(np.array([0.0, 1.0, 0.0])) > 0.99
    assert con.heading_constrained
    # Across the corridor every endpoint on a wall counts.
    assert con.information[1, 1] > 50.0


@pytest.mark.parametrize("pose", [Pose2D(1.0, 1.0, 0.3), Pose2D(5.2, 3.1, -2.0),
                                  Pose2D(3.0, 2.0, 1.0)])
def test_in_a_room_corner_nothing_is_unconstrained(pose):
    con = _constraint(_room(), pose)

    assert not con.degenerate
    assert con.unconstrained_directions() == []
    # The weakest direction still has some thirty endpoints' worth of wall (of 90).
    assert con.eigenvalues[0] > 5.0 * CONFIG.min_information


def test_in_an_open_hall_with_no_wall_in_range_nothing_is_constrained():
    con = _constraint(_hall(), Pose2D(20.0, 20.0, 0.0))

    assert con.constrained.tolist() == [False, False, False]
    assert not con.heading_constrained


def test_near_one_wall_across_and_heading_are_constrained_along_is_not():
    con = _constraint(_hall(), Pose2D(20.0, 3.0, 0.4))

    (free,) = con.unconstrained_directions()
    assert abs(free[0]) > 0.99
    assert con.heading_constrained


def test_project_keeps_the_step_only_along_constrained_directions():
    information = np.diag([0.0, 80.0, 300.0])  # a corridor along x
    con = degeneracy.constraint(information, length_scale=1.0, min_information=4.0)
    start = Pose2D(10.0, 0.5, 0.1)

    moved = con.project(start, Pose2D(10.3, 0.45, 0.12))

    assert moved.x == pytest.approx(10.0)
    assert moved.y == pytest.approx(0.45)
    assert moved.theta == pytest.approx(0.12)


def test_information_is_turned_into_the_map_frame_of_a_rotated_map():
    corridor = _corridor()
    rotated = Map(corridor.info.__class__(resolution=RES, width=corridor.info.width,
                                          height=corridor.info.height,
                                          origin=Pose2D(3.0, -2.0, math.pi / 2)),
                  corridor.data)
    # The same robot-frame scan, at the same place relative to the grid.
    points = scan_points(_ranges(corridor, Pose2D(25.0, 0.6, 0.0)), ANGLES, range_min=0.05,
                         range_max=RANGE, sensor_pose=Pose2D(), step=4)
    pose = rotated.info.origin.compose(Pose2D(25.0, 0.6, 0.0))
    information = ScanMatcher(build_likelihood_field(rotated)).information(points, pose)
    con = degeneracy.constraint(information, length_scale=1.0, min_information=4.0)

    # The grid's x axis is the map's y axis once the origin turns a quarter.
    (free,) = con.unconstrained_directions()
    assert abs(free[1]) > 0.99


def _feed(tracker: PoseTracker, grid: Map, true: Pose2D, odom: Pose2D, steps: int,
          start: int = 0) -> list:
    out = []
    for k in range(start, start + steps):
        now = 0.05 * k
        ranges = _ranges(grid, true, seed=k)
        scan = LaserScan(now, float(ANGLES[0]), 2.0 * math.pi / 360, 0.05, RANGE,
                         ranges.astype(np.float32))
        out.append(tracker.update(Odometry(now, odom, Twist()), None, scan, now))
    return out


def test_a_tracker_in_a_corridor_keeps_odometry_along_it_and_corrects_across():
    warm_up()
    grid = _corridor()
    true = Pose2D(25.0, 0.6, 0.0)
    tracker = PoseTracker(CONFIG)
    tracker.set_map(grid)
    tracker.initialize(true, 0.0)
    _feed(tracker, grid, true, Pose2D(), 5)
    assert tracker.estimate.state is LocalizationState.TRACKING
    # Odometry says the robot moved 0.1 m along and 0.1 m across, it did not: the scan can
    # undo the sideways step only.
    estimates = _feed(tracker, grid, true, Pose2D(0.1, 0.1, 0.0), 20, start=5)

    final = estimates[-1]
    assert final.state is LocalizationState.TRACKING
    assert final.quality > 0.9
    assert final.pose.y == pytest.approx(true.y, abs=0.02)
    assert final.pose.x == pytest.approx(true.x + 0.1, abs=0.02)


def test_a_tracker_in_an_open_hall_stays_tracking_on_odometry():
    warm_up()
    grid = _hall()
    tracker = PoseTracker(CONFIG)
    tracker.set_map(grid)
    near_wall = Pose2D(20.0, 3.0, 0.0)
    tracker.initialize(near_wall, 0.0)
    _feed(tracker, grid, near_wall, Pose2D(), 5)
    assert tracker.estimate.state is LocalizationState.TRACKING
    quality = tracker.estimate.quality

    # Carried 17 m into the middle (odometry agrees), then left there far longer than
    # lost_after: no return is within range, which contradicts nothing.
    middle = Pose2D(20.0, 20.0, 0.0)
    estimates = _feed(tracker, grid, middle, Pose2D(0.0, 17.0, 0.0), 200, start=5)

    assert {e.state for e in estimates} == {LocalizationState.TRACKING}
    assert estimates[-1].quality == pytest.approx(quality)
    assert estimates[-1].pose.distance_to(middle) < 0.02


def test_after_a_long_unconstrained_stretch_the_window_reaches_the_walls_that_come_into_view():
    warm_up()
    grid = _hall()
    tracker = PoseTracker(CONFIG)
    tracker.set_map(grid)
    start = Pose2D(20.0, 3.0, 0.0)
    tracker.initialize(start, 0.0)
    _feed(tracker, grid, start, Pose2D(), 5)
    assert tracker.estimate.state is LocalizationState.TRACKING

    # 38 m across the hall on odometry that comes out 0.4 m short; then the corner is in view.
    true = Pose2D(37.4, 37.0, 0.0)
    estimates = _feed(tracker, grid, true, Pose2D(17.0, 34.0, 0.0), 40, start=5)

    assert {e.state for e in estimates} == {LocalizationState.TRACKING}
    assert estimates[-1].pose.distance_to(true) < 0.02
    assert estimates[-1].quality > 0.9
    # Worked off in clamped steps, never in one jump.
    steps = [b.pose.distance_to(a.pose) for a, b in zip(estimates, estimates[1:], strict=False)]
    assert max(steps) <= CONFIG.max_correction_xy + 1e-6


def test_with_odometry_drift_off_the_fixed_window_does_not_reach_them():
    warm_up()
    grid = _hall()
    tracker = PoseTracker(PoseTrackerConfig(odometry_drift=0.0))
    tracker.set_map(grid)
    start = Pose2D(20.0, 3.0, 0.0)
    tracker.initialize(start, 0.0)
    _feed(tracker, grid, start, Pose2D(), 5)
    true = Pose2D(37.4, 37.0, 0.0)
    estimates = _feed(tracker, grid, true, Pose2D(17.0, 34.0, 0.0), 40, start=5)

    assert estimates[-1].pose.distance_to(true) > 0.2


def test_the_gyro_bias_is_learnt_where_walls_fix_heading_and_spares_the_heading_where_none_do():
    warm_up()
    grid = _hall()
    bias = 0.002  # [rad/s], a MEMS gyro's
    tracker = PoseTracker(CONFIG)
    tracker.set_map(grid)
    corner = Pose2D(3.0, 3.0, 0.5)
    tracker.initialize(corner, 0.0)
    now = 0.0

    def run(true: Pose2D, odom: Pose2D, seconds: float) -> None:
        nonlocal now
        for _ in range(round(seconds / 0.05)):
            now += 0.05
            ranges = _ranges(grid, true, seed=round(now * 20))
            scan = LaserScan(now, float(ANGLES[0]), 2.0 * math.pi / 360, 0.05, RANGE,
                             ranges.astype(np.float32))
            # The robot does not turn; the integrated gyro yaw drifts by the bias.
            imu = ImuReading(now, true.theta + bias * now, bias, 0.0)
            tracker.update(Odometry(now, odom, Twist()), imu, scan, now)

    run(corner, Pose2D(), 120.0)  # standing in a corner: the scan fixes heading
    assert tracker.gyro_bias == pytest.approx(bias, rel=0.1)

    # Carried into the middle of the hall (no wall in range) and left there for a minute: the
    # uncorrected bias would have turned the pose by 0.12 rad (7 degrees).
    middle = Pose2D(20.0, 20.0, 0.5)
    run(middle, corner.inverse().compose(middle), 60.0)
    assert tracker.estimate.state is LocalizationState.TRACKING
    assert abs(angle_diff(tracker.estimate.pose.theta, middle.theta)) < 0.015
