"""A polygon body in the simulator: its gap to walls, contact, and a mounted lidar."""

from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.geometry import Pose2D, Twist
from polynav.maps.ascii import map_from_ascii
from polynav.robot.profile import load_profile
from polynav.robot.sim.collision import body_wall_clearance
from polynav.robot.sim.config import SimConfig
from polynav.robot.sim.simulation import Simulation
from tests.unit.robot.sim.ascii_world import ascii_world

# One occupied cell at x 1.5..2.0, y 1.0..1.5, in a 3 m x 2.5 m grid of 0.5 m cells.
GRID = map_from_ascii(
    """
    ......
    ......
    ...#..
    ......
    ......
    """,
    resolution=0.5,
)
# A 0.6 m long, 0.2 m wide bar about its centre.
BAR = ((0.3, 0.1), (-0.3, 0.1), (-0.3, -0.1), (0.3, -0.1))


def _gap(pose: Pose2D) -> float:
    return body_wall_clearance(GRID.occupied(), GRID.info, pose, radius=0.32, polygon=BAR,
                               horizon=5.0)


def test_gap_from_a_polygon_depends_on_its_heading() -> None:
    # The bar's end faces the cell's west face 1.5 - (0.9 + 0.3) = 0.3 m away ...
    assert _gap(Pose2D(0.9, 1.25, 0.0)) == pytest.approx(0.3)
    # ... and turned across, its side is 1.5 - (0.9 + 0.1) = 0.5 m away.
    assert _gap(Pose2D(0.9, 1.25, math.pi / 2)) == pytest.approx(0.5)
    # A corner to a corner: bar corner (1.3, 0.9) to the cell's corner (1.5, 1.0).
    assert _gap(Pose2D(1.0, 0.8, 0.0)) == pytest.approx(math.hypot(0.2, 0.1))


def test_overlap_is_negative_and_deepens_as_the_body_pushes_in() -> None:
    shallow = _gap(Pose2D(1.25, 1.25, 0.0))  # the bar's end 0.05 m into the cell
    deep = _gap(Pose2D(1.4, 1.25, 0.0))
    assert shallow < 0.0 and deep < shallow


def test_a_disk_without_a_polygon_is_the_old_disk_check() -> None:
    gap = body_wall_clearance(GRID.occupied(), GRID.info, Pose2D(1.0, 1.25, 0.0), radius=0.2,
                              horizon=5.0)
    assert gap == pytest.approx(0.3)


def test_rectangular_base_turns_where_it_fits_and_not_where_its_corners_hit() -> None:
    # A corridor 0.6 m wide: the 0.51 x 0.43 base fits lengthwise but its diagonal (0.667 m)
    # does not, so turning across it is a collision while driving along it is none.
    world = ascii_world(
        "\n".join(["#" * 40] + ["." * 40] * 6 + ["#" * 40]), resolution=0.1,
        start=Pose2D(1.0, 0.4, 0.0),
    )
    profile = load_profile("research-base")
    sim = Simulation(world, config=profile.sim_config(), seed=1, people=False)
    sim.robot.drive(Twist(0.5, 0.0))
    for _ in range(50):
        sim.robot.drive(Twist(0.5, 0.0))
        sim.step()
    assert sim.collisions == []
    assert sim.true_pose.x > 1.3
    for _ in range(100):
        sim.robot.drive(Twist(0.0, 1.5))
        sim.step()
    assert len(sim.collisions) == 1
    assert abs(sim.true_pose.theta) < math.pi / 2  # stopped by its corners before crosswise


def test_lidar_mount_shifts_the_ranges_and_rides_on_the_scan() -> None:
    world = ascii_world("\n".join(["#" * 30] + ["#" + "." * 28 + "#"] * 10 + ["#" * 30]),
                        resolution=0.1, start=Pose2D(1.5, 0.6, 0.0))
    centre = Simulation(world, config=SimConfig(lidar_range_noise=0.0), seed=0, people=False)
    ahead = Simulation(world, config=SimConfig(lidar_range_noise=0.0, lidar_x=0.2), seed=0,
                       people=False)
    centre.step()
    ahead.step()
    a = centre.robot.read_scan()
    b = ahead.robot.read_scan()
    assert a is not None and b is not None
    forward = int(np.argmin(np.abs(a.angles)))
    assert b.ranges[forward] == pytest.approx(a.ranges[forward] - 0.2, abs=0.02)
    assert b.sensor_pose == Pose2D(0.2, 0.0, 0.0)
