from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.geometry import Pose2D
from polynav.maps import costs
from polynav.robot.interface import LaserScan
from polynav.runtime.local_move import (
    LocalMove,
    LocalMoveOutcome,
    free_distance_in_scan,
    free_distance_on_costmap,
)


class _WallAtX:
    """Costs with a lethal wall on x >= ``x``."""

    def __init__(self, x: float) -> None:
        self.x = x

    def cost_at(self, x: float, y: float) -> int:
        return costs.LETHAL if x >= self.x else costs.FREE


def _scan(ranges: list[float]) -> LaserScan:
    n = len(ranges)
    return LaserScan(stamp=0.0, angle_min=-math.pi, angle_increment=2 * math.pi / n,
                     range_min=0.05, range_max=10.0, ranges=np.array(ranges, dtype=np.float32))


def _move(**kwargs: float | None) -> LocalMove:
    values: dict[str, object] = dict(rotate=None, distance=None, yaw=0.0,
                                     odometry_pose=Pose2D(), max_linear_velocity=0.5,
                                     max_angular_velocity=1.0, stop_distance=0.3)
    values.update(kwargs)
    return LocalMove(**values)  # type: ignore[arg-type]


def test_costmap_free_distance_is_to_the_robot_edge() -> None:
    free = free_distance_on_costmap(_WallAtX(3.0), Pose2D(1.0, 0.0, 0.0), direction=1.0,
                                    robot_radius=0.25, horizon=5.0, step=0.025)
    assert free == pytest.approx(1.75, abs=0.025)


def test_costmap_free_distance_backwards_and_beyond_the_horizon() -> None:
    wall = _WallAtX(3.0)
    assert free_distance_on_costmap(wall, Pose2D(1.0, 0.0, 0.0), direction=-1.0,
                                    robot_radius=0.25, horizon=5.0, step=0.025) == math.inf
    assert free_distance_on_costmap(wall, Pose2D(1.0, 0.0, 0.0), direction=1.0,
                                    robot_radius=0.25, horizon=1.0, step=0.025) == math.inf


def test_scan_free_distance_counts_returns_in_the_robot_corridor_only() -> None:
    ranges = [math.inf] * 360
    ranges[180] = 2.0          # straight ahead (angle 0)
    ranges[90] = 0.5           # to the right (-pi/2): beside, not ahead
    scan = _scan(ranges)
    assert free_distance_in_scan(scan, direction=1.0, robot_radius=0.25) == pytest.approx(1.75)
    assert free_distance_in_scan(scan, direction=-1.0, robot_radius=0.25) == math.inf


def test_rotation_ends_within_tolerance_and_turns_the_short_way_back_after_overshoot() -> None:
    move = _move(rotate=1.0)
    first = move.tick(yaw=0.0, odometry_pose=Pose2D(), free_ahead=math.inf)
    assert first is not None
    assert first.angular == 1.0
    back = move.tick(yaw=1.1, odometry_pose=Pose2D(), free_ahead=math.inf)
    assert back is not None
    assert back.angular < 0.0
    assert move.tick(yaw=1.005, odometry_pose=Pose2D(), free_ahead=math.inf) is None
    assert move.outcome is LocalMoveOutcome.DONE


def test_rotation_counts_full_turns_across_the_wrap() -> None:
    move = _move(rotate=2 * math.pi)
    yaw = 0.0
    for _ in range(7):
        yaw = math.remainder(yaw + 0.9, 2 * math.pi)
        assert move.tick(yaw=yaw, odometry_pose=Pose2D(), free_ahead=math.inf) is not None
    assert move.outcome is LocalMoveOutcome.RUNNING  # 6.3 rad turned: just past one turn


def test_straight_move_slows_near_the_end_and_stops_at_the_distance() -> None:
    move = _move(distance=1.0)
    far = move.tick(yaw=0.0, odometry_pose=Pose2D(), free_ahead=math.inf)
    near = move.tick(yaw=0.0, odometry_pose=Pose2D(0.95, 0.0, 0.0), free_ahead=math.inf)
    assert far is not None and near is not None
    assert far.linear == 0.5
    assert 0.0 < near.linear < 0.25
    assert move.tick(yaw=0.0, odometry_pose=Pose2D(0.995, 0.0, 0.0), free_ahead=1.0) is None
    assert move.outcome is LocalMoveOutcome.DONE


def test_straight_move_ends_blocked_when_the_way_closes() -> None:
    move = _move(distance=2.0)
    assert move.tick(yaw=0.0, odometry_pose=Pose2D(), free_ahead=1.0) is not None
    assert move.tick(yaw=0.0, odometry_pose=Pose2D(0.5, 0.0, 0.0), free_ahead=0.29) is None
    assert move.outcome is LocalMoveOutcome.BLOCKED


def test_an_obstacle_beyond_the_distance_does_not_block() -> None:
    move = _move(distance=0.2)
    twist = move.tick(yaw=0.0, odometry_pose=Pose2D(), free_ahead=0.25)
    assert twist is not None
    assert twist.linear > 0.0


def test_straight_move_holds_its_heading() -> None:
    move = _move(distance=1.0)
    twist = move.tick(yaw=0.1, odometry_pose=Pose2D(), free_ahead=math.inf)
    assert twist is not None
    assert twist.angular == pytest.approx(-0.2)
