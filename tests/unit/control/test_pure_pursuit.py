"""Regulated pure pursuit on an exact unicycle, on empty and obstructed cost grids."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest

from polynav.control.interface import ControlStatus
from polynav.control.pure_pursuit import PurePursuitConfig, RegulatedPurePursuit
from polynav.errors import ConfigError
from polynav.geometry import Pose2D, Twist
from polynav.maps import costs
from polynav.maps.map import MapInfo
from polynav.planning.path import Path

DT = 0.05
CFG = PurePursuitConfig()


@dataclass(frozen=True)
class Grid:
    info: MapInfo
    costs: np.ndarray


def empty_grid(size_m: float = 20.0, res: float = 0.05) -> Grid:
    n = int(size_m / res)
    return Grid(MapInfo(res, n, n, Pose2D(-size_m / 2, -size_m / 2, 0.0)),
                np.zeros((n, n), dtype=np.uint8))


def polyline(*corners: tuple[float, float], spacing: float = 0.05) -> Path:
    pts = [np.array(corners[0], dtype=float)]
    for a, b in zip(corners, corners[1:], strict=False):
        a_, b_ = np.array(a, float), np.array(b, float)
        n = max(1, int(math.ceil(np.linalg.norm(b_ - a_) / spacing)))
        for k in range(1, n + 1):
            pts.append(a_ + (b_ - a_) * k / n)
    return Path(np.array(pts))


@dataclass
class Run:
    pose: Pose2D
    commands: list[Twist]
    statuses: list[ControlStatus]


def drive(controller: RegulatedPurePursuit, start: Pose2D, grid: Grid, *, seconds: float = 60.0,
          noise: float = 0.0, seed: int = 0) -> Run:
    """Integrate exact unicycle motion under the controller's commands until it arrives."""
    rng = np.random.default_rng(seed)
    pose, velocity = start, Twist()
    commands: list[Twist] = []
    statuses: list[ControlStatus] = []
    for _ in range(int(seconds / DT)):
        seen = pose
        if noise:
            seen = Pose2D(pose.x + rng.normal(0, noise), pose.y + rng.normal(0, noise),
                          pose.theta + rng.normal(0, noise))
        cmd = controller.compute(seen, velocity, grid, DT)
        commands.append(cmd.twist)
        statuses.append(cmd.status)
        if cmd.status is ControlStatus.ARRIVED:
            break
        v, w = cmd.twist.linear, cmd.twist.angular
        if abs(w) < 1e-9:
            pose = Pose2D(pose.x + v * DT * math.cos(pose.theta),
                          pose.y + v * DT * math.sin(pose.theta), pose.theta)
        else:
            th = pose.theta + w * DT
            pose = Pose2D(pose.x + v / w * (math.sin(th) - math.sin(pose.theta)),
                          pose.y - v / w * (math.cos(th) - math.cos(pose.theta)), th)
        velocity = cmd.twist
    return Run(pose, commands, statuses)


def assert_within_limits(run: Run, cfg: PurePursuitConfig = CFG) -> None:
    prev = Twist()
    for cmd in run.commands:
        assert abs(cmd.linear) <= cfg.max_linear_velocity + 1e-9
        assert abs(cmd.angular) <= cfg.max_angular_velocity + 1e-9
        assert cmd.linear >= 0.0
        if cmd.linear > prev.linear:
            assert (cmd.linear - prev.linear) / DT <= cfg.linear_acceleration + 1e-6
        elif cmd.linear > 0.0:  # slowing, not an emergency stop
            assert (prev.linear - cmd.linear) / DT <= cfg.linear_deceleration + 1e-6
        if cmd.linear == 0.0 and prev.linear == 0.0 and cmd.angular != 0.0:
            assert abs(cmd.angular - prev.angular) / DT <= cfg.angular_acceleration + 1e-6
        prev = cmd


def assert_arrived(run: Run, goal: Pose2D, xy: float = 0.02, yaw: float = 0.05) -> None:
    assert run.statuses[-1] is ControlStatus.ARRIVED
    assert run.pose.distance_to(goal) <= xy
    assert abs(run.pose.heading_error_to(goal)) <= yaw


def test_follows_a_straight_path_and_stops_on_the_goal() -> None:
    ctrl = RegulatedPurePursuit()
    goal = Pose2D(6.0, 0.0, 0.0)
    ctrl.set_path(polyline((0.0, 0.0), (6.0, 0.0)), goal)
    run = drive(ctrl, Pose2D(0.0, 0.0, 0.0), empty_grid())
    assert_arrived(run, goal)
    assert_within_limits(run)
    assert max(c.linear for c in run.commands) == pytest.approx(CFG.max_linear_velocity)


def test_follows_an_l_shaped_path() -> None:
    ctrl = RegulatedPurePursuit()
    goal = Pose2D(4.0, 4.0, math.pi / 2)
    ctrl.set_path(polyline((0.0, 0.0), (4.0, 0.0), (4.0, 4.0)), goal)
    run = drive(ctrl, Pose2D(0.0, 0.0, 0.0), empty_grid())
    assert_arrived(run, goal)
    assert_within_limits(run)


def test_u_turn_ends_facing_back() -> None:
    ctrl = RegulatedPurePursuit()
    goal = Pose2D(0.0, 1.5, math.pi)
    ctrl.set_path(polyline((0.0, 0.0), (4.0, 0.0), (4.0, 1.5), (0.0, 1.5)), goal)
    run = drive(ctrl, Pose2D(0.0, 0.0, 0.0), empty_grid())
    assert_arrived(run, goal)
    assert_within_limits(run)


def test_path_behind_the_robot_starts_with_a_turn_in_place() -> None:
    ctrl = RegulatedPurePursuit()
    goal = Pose2D(-3.0, 0.0, math.pi)
    ctrl.set_path(polyline((0.0, 0.0), (-3.0, 0.0)), goal)
    run = drive(ctrl, Pose2D(0.0, 0.0, 0.0), empty_grid())
    assert run.statuses[0] is ControlStatus.ROTATING
    first_drive = next(i for i, c in enumerate(run.commands) if c.linear > 0)
    assert all(c.linear == 0.0 for c in run.commands[:first_drive])
    assert all(s is ControlStatus.ROTATING for s in run.statuses[:first_drive])
    assert_arrived(run, goal)


@pytest.mark.parametrize("seed", range(12))
def test_random_goals_end_precisely(seed: int) -> None:
    rng = np.random.default_rng(seed)
    start = Pose2D(0.0, 0.0, rng.uniform(-math.pi, math.pi))
    mid = (rng.uniform(-4, 4), rng.uniform(-4, 4))
    end = (rng.uniform(-4, 4), rng.uniform(-4, 4))
    goal = Pose2D(*end, rng.uniform(-math.pi, math.pi))
    ctrl = RegulatedPurePursuit()
    ctrl.set_path(polyline((0.0, 0.0), mid, end), goal)
    run = drive(ctrl, start, empty_grid())
    assert_arrived(run, goal)
    assert_within_limits(run)


@pytest.mark.parametrize("seed", range(6))
def test_pose_noise_of_two_centimetres_still_ends_within_five(seed: int) -> None:
    rng = np.random.default_rng(100 + seed)
    goal = Pose2D(rng.uniform(2, 5), rng.uniform(-3, 3), rng.uniform(-math.pi, math.pi))
    ctrl = RegulatedPurePursuit()
    ctrl.set_path(polyline((0.0, 0.0), (goal.x, goal.y)), goal)
    run = drive(ctrl, Pose2D(0.0, 0.0, 0.0), empty_grid(), noise=0.02 / math.sqrt(2),
                seed=seed)
    assert run.statuses[-1] is ControlStatus.ARRIVED
    assert run.pose.distance_to(goal) <= 0.05 + 0.03
    assert abs(run.pose.heading_error_to(goal)) <= 0.05 + 0.03


def test_obstacle_on_the_path_blocks_before_it_is_reached() -> None:
    grid = empty_grid()
    ix, iy = grid.info.world_to_cell(3.0, 0.0)
    grid.costs[iy - 2 : iy + 3, ix - 2 : ix + 3] = costs.LETHAL
    ctrl = RegulatedPurePursuit()
    ctrl.set_path(polyline((0.0, 0.0), (6.0, 0.0)), Pose2D(6.0, 0.0, 0.0))
    run = drive(ctrl, Pose2D(0.0, 0.0, 0.0), grid, seconds=20.0)
    blocked = run.statuses.index(ControlStatus.BLOCKED)
    assert run.commands[blocked] == Twist()
    assert ControlStatus.SLOWING in run.statuses[:blocked]
    assert run.pose.x < 3.0 - 0.1 - 0.25  # never touches it: front of the robot clear of it
    assert ControlStatus.ARRIVED not in run.statuses


def test_obstacle_farther_ahead_slows_the_robot() -> None:
    grid = empty_grid()
    ix, iy = grid.info.world_to_cell(4.0, 0.0)
    grid.costs[iy, ix] = costs.INSCRIBED
    ctrl = RegulatedPurePursuit()
    ctrl.set_path(polyline((0.0, 0.0), (8.0, 0.0)), Pose2D(8.0, 0.0, 0.0))
    at_speed = Twist(CFG.max_linear_velocity, 0.0)
    free = ctrl.compute(Pose2D(0.0, 0.0, 0.0), at_speed, empty_grid(), DT)
    near = ctrl.compute(Pose2D(3.0, 0.0, 0.0), at_speed, grid, DT)
    assert free.status is ControlStatus.TRACKING
    assert near.status is ControlStatus.SLOWING
    assert near.twist.linear < free.twist.linear


def test_inflation_under_the_robot_lowers_the_speed() -> None:
    grid = empty_grid()
    grid.costs[:, :] = 200
    ctrl = RegulatedPurePursuit()
    ctrl.set_path(polyline((0.0, 0.0), (8.0, 0.0)), Pose2D(8.0, 0.0, 0.0))
    cmd = ctrl.compute(Pose2D(0.0, 0.0, 0.0), Twist(0.4, 0.0), grid, DT)
    expected = CFG.max_linear_velocity * (1 - CFG.proximity_slowdown * 200 / 252)
    assert cmd.twist.linear == pytest.approx(expected)


def test_start_in_inscribed_cell_does_not_block_the_escape() -> None:
    grid = empty_grid()
    ix0, iy0 = grid.info.world_to_cell(0.0, 0.0)
    grid.costs[iy0 - 3 : iy0 + 4, ix0 - 3 : ix0 + 4] = costs.INSCRIBED
    ctrl = RegulatedPurePursuit()
    ctrl.set_path(polyline((0.0, 0.0), (3.0, 0.0)), Pose2D(3.0, 0.0, 0.0))
    cmd = ctrl.compute(Pose2D(0.0, 0.0, 0.0), Twist(), grid, DT)
    assert cmd.status is not ControlStatus.BLOCKED
    assert cmd.twist.linear > 0.0


def test_goal_latch_keeps_turning_in_place_despite_jitter() -> None:
    ctrl = RegulatedPurePursuit()
    goal = Pose2D(1.0, 0.0, math.pi / 2)
    ctrl.set_path(polyline((0.0, 0.0), (1.0, 0.0)), goal)
    cmd = ctrl.compute(Pose2D(0.97, 0.0, 0.0), Twist(), empty_grid(), DT)
    assert cmd.status is ControlStatus.TRACKING  # within tolerance, but the goal is still ahead
    cmd = ctrl.compute(Pose2D(0.99, 0.0, 0.0), Twist(), empty_grid(), DT)
    assert cmd.status is ControlStatus.ROTATING
    # The estimate jitters 6 cm away while turning: no driving again.
    cmd = ctrl.compute(Pose2D(0.94, 0.0, 0.5), Twist(0.0, 0.5), empty_grid(), DT)
    assert cmd.status is ControlStatus.ROTATING and cmd.twist.linear == 0.0
    cmd = ctrl.compute(Pose2D(0.94, 0.0, math.pi / 2 - 0.01), Twist(0.0, 0.1), empty_grid(), DT)
    assert cmd.status is ControlStatus.ARRIVED and cmd.twist == Twist()


def test_reset_forgets_the_path() -> None:
    ctrl = RegulatedPurePursuit()
    ctrl.set_path(polyline((0.0, 0.0), (1.0, 0.0)), Pose2D(1.0, 0.0, 0.0))
    ctrl.reset()
    cmd = ctrl.compute(Pose2D(), Twist(), empty_grid(), DT)
    assert cmd.twist == Twist()


@pytest.mark.parametrize(
    ("field", "value"),
    [("max_linear_velocity", 0.0), ("min_lookahead", -1.0), ("max_lookahead", 0.1),
     ("proximity_slowdown", 1.0), ("slowdown_distance", 0.1), ("min_regulated_speed", 5.0)],
)
def test_config_rejects_bad_values(field: str, value: float) -> None:
    with pytest.raises(ConfigError) as err:
        PurePursuitConfig(**{field: value})
    assert f"control.pure_pursuit.{field}" in str(err.value)
