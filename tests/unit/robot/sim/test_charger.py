"""The simulated charger: a plate the lidar sees and the base bumps into, a beacon seen from in
front only, and a data link and mains whose faults keep the current off."""

from __future__ import annotations

import math
from dataclasses import replace

import pytest

from polynav.docking.detector import find_dock, points_of_scan
from polynav.docking.shape import DockShape, face_of
from polynav.errors import InvalidRequest
from polynav.geometry import Pose2D, Twist, angle_diff
from polynav.nav.stack import stack_config_for
from polynav.robot.interface import DockLink
from polynav.robot.profile import DEFAULT_PROFILE, load_profile
from polynav.robot.sim.config import SimConfig
from polynav.robot.sim.simulation import Simulation
from polynav.site import PointKind
from polynav.worlds.world import World
from tests.unit.robot.sim.ascii_world import ascii_world

QUIET = SimConfig(lidar_range_noise=0.0, odom_translation_noise=0.0, odom_rotation_noise=0.0,
                  imu_yaw_rate_noise=0.0, imu_yaw_rate_bias=0.0)
HALL = "\n".join(["#" * 100] + ["#" + "." * 98 + "#"] * 38 + ["#" * 100])  # 10 m x 4 m
CHARGER = Pose2D(2.0, 2.0, math.pi)  # docked facing -x: the plate's face at x = 1.75


def _world(start: Pose2D) -> World:
    return ascii_world(HALL, start=start, points=(("charger", CHARGER, PointKind.CHARGER),))


def _run(sim: Simulation, seconds: float) -> None:
    for _ in range(round(seconds / sim.config.physics_period)):
        sim.step()


def test_the_lidar_sees_the_plate_where_the_charger_is() -> None:
    start = CHARGER.compose(Pose2D(-0.6, 0.05, 0.1))
    sim = Simulation(_world(start), config=QUIET, people=False)
    sim.step()
    assert sim.scan is not None
    points = points_of_scan(sim.scan, sim.true_pose)
    face = face_of(CHARGER, QUIET.robot_radius)
    found = find_dock(points, face.compose(Pose2D(0.05, -0.05, 0.08)), DockShape())
    assert found is not None
    assert found.pose.distance_to(face) < 0.01
    assert abs(angle_diff(found.pose.theta, face.theta)) < math.radians(1.0)


def test_driving_into_the_plate_is_a_collision() -> None:
    sim = Simulation(_world(CHARGER.compose(Pose2D(-0.3, 0.0, 0.0))), config=QUIET,
                     people=False)
    sim.robot.drive(Twist(0.3, 0.0))
    _run(sim, 3.0)
    assert [c.obstacle for c in sim.collisions] == ["wall"]
    along = sim.true_pose.relative_to(CHARGER).x
    assert 0.0 < along < 0.06  # past the charger point by no more than the notch lets it


def test_on_the_charger_the_link_is_valid_and_the_current_flows() -> None:
    sim = Simulation(_world(CHARGER), config=QUIET, people=False)
    _run(sim, 1.0)
    signals = sim.dock_signals()
    assert (signals.beacon, signals.contact, signals.link) == (True, True, DockLink.VALID)
    assert sim.battery.charging


@pytest.mark.parametrize(("fault", "link", "beacon"), [
    ("charger_link_invalid", DockLink.INVALID, True),
    ("charger_no_power", DockLink.VALID, True),
    ("charger_beacon_off", DockLink.VALID, False),
])
def test_a_broken_charger(fault: str, link: DockLink, beacon: bool) -> None:
    sim = Simulation(_world(CHARGER), config=QUIET, people=False)
    sim.inject_fault(fault)
    _run(sim, 1.0)
    signals = sim.dock_signals()
    assert (signals.beacon, signals.contact, signals.link) == (beacon, True, link)
    assert sim.battery.charging is (fault == "charger_beacon_off")


@pytest.mark.parametrize(("where", "seen"), [
    (Pose2D(-1.0, 0.0, 0.0), True),  # a metre in front, facing it
    (Pose2D(-1.0, 0.3, -0.2), True),  # off the axis, within the cone
    (Pose2D(-1.0, 0.0, math.pi), False),  # facing away
    (Pose2D(-0.3, 1.0, -math.pi / 2), False),  # beside it, outside the cone
    (Pose2D(-3.5, 0.0, 0.0), False),  # beyond the range
])
def test_the_beacon_is_seen_from_in_front_only(where: Pose2D, seen: bool) -> None:
    start = CHARGER.compose(where)
    start = Pose2D(min(max(start.x, 0.4), 9.6), min(max(start.y, 0.4), 3.6), start.theta)
    sim = Simulation(_world(start), config=QUIET, people=False)
    assert sim.dock_signals().beacon is seen
    assert not sim.dock_signals().contact


def test_an_unknown_fault_is_refused() -> None:
    sim = Simulation(_world(CHARGER), config=QUIET, people=False)
    with pytest.raises(InvalidRequest, match="charger_beacon_off"):
        sim.inject_fault("charger_on_fire")


def test_the_profile_sizes_the_plate_for_the_simulator_and_the_navigator() -> None:
    base = load_profile(DEFAULT_PROFILE)
    wide = replace(base, charger=replace(base.charger, plate_width=0.8, notch_width=0.4))
    plate = DockShape(0.8, 0.4, 0.1)
    assert wide.sim_config().charger_plate == plate
    assert stack_config_for(wide).navigator.dock_plate == plate
    sim = Simulation(_world(CHARGER), config=wide.sim_config(QUIET), people=False)
    segments = sim.scene.floors["ground"].charger_segments
    ys = segments[:, [1, 3]]
    assert abs(float(ys.max() - ys.min()) - 0.8) < 1e-9
