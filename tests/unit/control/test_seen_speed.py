"""The controller drives no faster than it can stop within the floor it has seen (issue 31)."""

from __future__ import annotations

import pytest

from polynav.control import regulation
from polynav.control.interface import ControlStatus
from polynav.control.pure_pursuit import PurePursuitConfig, RegulatedPurePursuit
from polynav.footprint import Footprint
from polynav.geometry import Pose2D, Twist
from polynav.maps import costs
from tests.unit.control.unicycle import DT, empty_grid, polyline, step

FAST = PurePursuitConfig(pose_filter_gain=1.0, max_linear_velocity=2.0, linear_acceleration=1.2,
                         linear_deceleration=2.0, lookahead_time=0.5)
BODY = Footprint.rectangle(0.51, 0.43)


def test_seen_speed_stops_within_the_seen_distance() -> None:
    for distance in (0.05, 0.5, 1.0, 3.0):
        v = regulation.seen_speed(distance, deceleration=2.0, latency=0.15)
        assert v * 0.15 + v * v / (2.0 * 2.0) == pytest.approx(distance)
    assert regulation.seen_speed(0.0, deceleration=2.0, latency=0.15) == 0.0
    assert regulation.seen_speed(-1.0, deceleration=2.0, latency=0.15) == 0.0


def test_unknown_floor_ahead_caps_the_speed_and_known_floor_does_not() -> None:
    # A straight path whose far part the sensors have not seen: at 2 m/s the robot needs
    # 0.3 m of latency and 1 m of braking; 0.75 m of seen floor ahead allows less.
    path, goal = polyline((0.0, 0.0), (8.0, 0.0)), Pose2D(8.0, 0.0, 0.0)
    seen_to = 1.0  # [m] the unknown starts here, the body's front 0.255 m ahead of the centre
    grid = empty_grid()
    grid.costs[:, round((seen_to + 10.0) / 0.05):] = costs.UNKNOWN
    ctrl = RegulatedPurePursuit(FAST, footprint=BODY)
    ctrl.set_path(path, goal)
    cmd = ctrl.compute(Pose2D(0.0, 0.0, 0.0), Twist(2.0, 0.0), grid, DT)
    room = seen_to - 0.255  # where the body's front would first reach the unknown
    cap = regulation.seen_speed(room, deceleration=FAST.linear_deceleration,
                                latency=FAST.sight_latency)
    assert cap < 1.8
    assert cmd.status is ControlStatus.SLOWING
    assert cmd.twist.linear == pytest.approx(
        max(cap, 2.0 - FAST.linear_deceleration * DT), abs=0.03)
    # The same path, all seen: full speed.
    ctrl = RegulatedPurePursuit(FAST, footprint=BODY)
    ctrl.set_path(path, goal)
    cmd = ctrl.compute(Pose2D(0.0, 0.0, 0.0), Twist(2.0, 0.0), empty_grid(), DT)
    assert cmd.status is ControlStatus.TRACKING and cmd.twist.linear == pytest.approx(2.0)


def test_a_robot_stops_short_of_a_wall_it_sees_only_on_arrival() -> None:
    # Driving into unknown space that holds a wall, seen (marked) only once the robot comes
    # within 1 m of it. The base brakes at its deceleration limit, even when told to stop at
    # once: slowed to the floor it has seen, the robot stops before the wall; at full speed
    # (what the clearance alone allowed) it would need 1.3 m to stop.
    path, goal = polyline((0.0, 0.0), (8.0, 0.0)), Pose2D(8.0, 0.0, 0.0)
    wall_x, sight, front = 5.0, 1.0, 0.255
    ctrl = RegulatedPurePursuit(FAST, footprint=BODY)
    ctrl.set_path(path, goal)
    pose, velocity = Pose2D(), Twist()
    for _ in range(round(20.0 / DT)):
        grid = empty_grid()
        grid.costs[:, round((pose.x + sight + 10.0) / 0.05):] = costs.UNKNOWN
        if pose.x + sight >= wall_x:
            grid.costs[:, round((wall_x + 10.0) / 0.05):] = costs.LETHAL
        cmd = ctrl.compute(pose, velocity, grid, DT)
        v = max(cmd.twist.linear, velocity.linear - FAST.linear_deceleration * DT)
        velocity = Twist(v, 0.0)
        pose = step(pose, velocity)
        assert pose.x + front < wall_x, "the body reached the wall"
        if velocity.linear == 0.0 and cmd.status is ControlStatus.BLOCKED:
            break
    assert cmd.status is ControlStatus.BLOCKED
    assert pose.x > wall_x - 1.5  # it got there, not creeping from the start
