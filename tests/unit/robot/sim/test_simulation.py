from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.errors import InvalidRequest
from polynav.geometry import Pose2D, Twist
from polynav.robot.interface import Robot
from polynav.robot.sim.collision import person_clearance, wall_clearance
from polynav.robot.sim.config import SimConfig
from polynav.robot.sim.simulation import Simulation
from polynav.site import PointKind
from polynav.worlds.world import PersonRoute, World
from tests.unit.robot.sim.ascii_world import ascii_world

QUIET = SimConfig(lidar_range_noise=0.0, odom_translation_noise=0.0, odom_rotation_noise=0.0,
                  odom_translation_additive=0.0, odom_rotation_additive=0.0, person_pause=0.0)


def _room(width: int, height: int) -> str:
    """A walled room of width x height cells."""
    inner = "#" + "." * (width - 2) + "#"
    return "\n".join(["#" * width] + [inner] * (height - 2) + ["#" * width])


# 10 m x 2 m at 0.1 m: the free interior spans x 0.1..9.9, y 0.1..1.9.
CORRIDOR = _room(100, 20)
# 10 m x 4 m: free x 0.1..9.9, y 0.1..3.9.
HALL = _room(100, 40)


def _corridor(**kwargs: object) -> World:
    return ascii_world(CORRIDOR, start=Pose2D(0.6, 1.0, 0.0), **kwargs)  # type: ignore[arg-type]


def _run(sim: Simulation, seconds: float) -> None:
    for _ in range(round(seconds / sim.config.physics_period)):
        sim.step()


def test_simulation_starts_at_the_start_pose_on_its_own_clock() -> None:
    sim = Simulation(_corridor(), config=QUIET)
    assert sim.clock.now() == 0.0
    assert sim.floor == "ground"
    assert sim.true_pose == Pose2D(0.6, 1.0, 0.0)
    assert sim.true_twist == Twist()
    assert sim.robot.read_scan() is None and sim.robot.read_imu() is None
    assert sim.robot.read_odometry().pose == Pose2D(0.0, 0.0, 0.0)
    sim.step()
    assert sim.clock.now() == 0.02
    scan, imu = sim.robot.read_scan(), sim.robot.read_imu()
    assert scan is not None and scan.stamp == 0.02
    assert imu is not None and imu.stamp == 0.02


def test_odometry_starts_at_zero_at_a_turned_start_pose_and_follows_in_its_own_frame() -> None:
    start = Pose2D(3.0, 2.5, math.pi / 2)
    sim = Simulation(ascii_world(HALL, start=start), config=QUIET)
    assert sim.odometry.pose == Pose2D(0.0, 0.0, 0.0)
    assert sim.odometry_origin == start and sim.true_pose == start
    sim.robot.drive(Twist(0.5, 0.4))  # an arc to the left, from facing +y
    _run(sim, 2.0)
    true, odom = sim.true_pose, sim.odometry.pose
    # Noise-free: the odometry is the true motion seen from the start pose, not the world pose.
    seen = sim.world_to_odometry(true)
    assert (odom.x, odom.y, odom.theta) == pytest.approx((seen.x, seen.y, seen.theta), abs=1e-9)
    assert odom.theta == pytest.approx(true.theta - math.pi / 2, abs=1e-9)
    assert odom.x > 0.5 and odom.y > 0.1 and true.y > 3.0 and true.x < 3.0
    assert sim.odometry_to_world(odom).distance_to(true) < 1e-9
    before = sim.odometry
    sim.teleport(sim.floor, Pose2D(6.0, 2.0, 0.0))  # a ride moves the body, not the frame
    assert sim.odometry == before and sim.odometry_origin == start


def test_sim_robot_is_a_robot_reading_the_simulation() -> None:
    sim = Simulation(_corridor(), config=QUIET)
    robot: Robot = sim.robot
    robot.drive(Twist(0.5, 0.0))
    _run(sim, 1.0)
    assert robot.read_odometry() == sim.odometry
    assert robot.read_scan() is sim.scan
    assert robot.read_imu() == sim.imu
    assert robot.read_battery() == sim.battery
    assert robot.estop_pressed() is False
    assert sim.true_twist.linear == pytest.approx(0.5)


def test_step_with_a_duration_substeps_at_the_physics_period() -> None:
    one, two = Simulation(_corridor(), seed=3), Simulation(_corridor(), seed=3)
    for sim in (one, two):
        sim.robot.drive(Twist(0.8, 0.5))
    for _ in range(10):
        one.step(0.1)
    _run(two, 1.0)
    assert one.clock.now() == pytest.approx(1.0)
    assert one.true_pose == two.true_pose
    assert one.odometry == two.odometry
    with pytest.raises(InvalidRequest):
        one.step(0.0)


def test_sensors_publish_at_their_rates() -> None:
    sim = Simulation(_corridor())
    scans, imus = set(), set()
    for _ in range(500):
        sim.step()
        scan, imu = sim.robot.read_scan(), sim.robot.read_imu()
        assert scan is not None and imu is not None
        scans.add(scan.stamp)
        imus.add(imu.stamp)
    # Due every 1/15 s from t = 0, each taken at the first physics step at or after its time.
    assert len(scans) == 151
    gaps = np.diff(sorted(scans))
    assert set(np.round(gaps, 9)) == {0.06, 0.08}
    assert len(imus) == 500


def test_estop_brakes_from_the_next_step_at_the_deceleration_and_ignores_drive() -> None:
    # Expectation: the step after the press already brakes, at linear_deceleration (2.5 m/s²),
    # so from 1.0 m/s the base loses 0.05 m/s per 1/50 s step, stands still after 20 steps
    # (0.4 s), and has rolled v² / 2a = 0.2 m.
    sim = Simulation(_corridor(), config=QUIET)
    sim.robot.drive(Twist(1.0, 0.0))
    _run(sim, 1.2)
    assert sim.true_twist.linear == 1.0
    pressed_at = sim.true_pose
    sim.press_estop()
    assert sim.robot.estop_pressed()
    sim.step()
    assert sim.true_twist.linear == pytest.approx(0.95, abs=1e-12)
    for _ in range(18):
        sim.step()
    assert sim.true_twist.linear == pytest.approx(0.05, abs=1e-12)
    sim.step()
    assert sim.true_twist.linear == 0.0
    assert sim.true_pose.x - pressed_at.x == pytest.approx(0.2, abs=1e-12)
    stopped = sim.true_pose
    sim.robot.drive(Twist(1.0, 1.0))
    _run(sim, 1.0)
    assert sim.true_pose == stopped
    # Released, the base does not resume the command it had before the press.
    sim.release_estop()
    assert not sim.robot.estop_pressed()
    _run(sim, 0.5)
    assert sim.true_pose == stopped
    sim.robot.drive(Twist(0.3, 0.0))
    _run(sim, 0.5)
    assert sim.true_pose.x > stopped.x


def test_driving_into_a_wall_records_one_collision_and_stops_the_base() -> None:
    sim = Simulation(ascii_world(CORRIDOR, start=Pose2D(8.5, 1.0, 0.0)), config=QUIET)
    sim.robot.drive(Twist(0.5, 0.0))
    occupied = sim.world.floor("ground").map.occupied()
    info = sim.world.floor("ground").map.info
    stopped_at = None
    for _ in range(round(5.0 / 0.02)):  # keep pushing for 5 s
        sim.step()
        gap = wall_clearance(occupied, info, sim.true_pose.x, sim.true_pose.y, radius=0.25,
                             horizon=1.0)
        assert gap >= 0.0
        if sim.collisions and stopped_at is None:
            stopped_at = sim.clock.now()
            assert sim.true_twist == Twist()
    assert len(sim.collisions) == 1
    hit = sim.collisions[0]
    assert hit.obstacle == "wall"
    assert hit.stamp == stopped_at
    # Contact at x = 9.9 - 0.25 = 9.65, reached after the 0.5 s ramp and 0.78 m more.
    assert 9.6 < hit.pose.x <= 9.65
    assert stopped_at == pytest.approx(0.5 + (9.65 - 8.5 - 0.125) / 0.5, abs=0.03)
    # Backing off ends the contact; driving in again is a new collision.
    sim.robot.drive(Twist(-0.3, 0.0))
    _run(sim, 1.0)
    assert len(sim.collisions) == 1
    sim.robot.drive(Twist(0.3, 0.0))
    _run(sim, 2.0)
    assert len(sim.collisions) == 2


def test_robot_may_back_out_of_a_tight_spot_it_was_teleported_into() -> None:
    sim = Simulation(_corridor(), config=QUIET)
    sim.teleport("ground", Pose2D(9.65, 1.0, 0.0))  # touching the east wall
    sim.robot.drive(Twist(-0.2, 0.0))
    _run(sim, 0.5)
    assert sim.true_pose.x < 9.6
    assert sim.collisions == []


def _hall_with_walker(speed: float = 1.0) -> World:
    walker = PersonRoute(((5.0, 0.5), (5.0, 3.5)), speed=speed, loop=False)
    return ascii_world(HALL, start=Pose2D(2.0, 2.0, 0.0), people=(walker,))


def test_a_walking_person_blocks_the_lidar_while_crossing_in_front() -> None:
    # Scans every 0.1 s land exactly on the walker's timetable: at t = 1.5 s it is at (5, 2).
    config = SimConfig(lidar_range_noise=0.0, lidar_rate=10.0, person_pause=0.0)
    sim = Simulation(_hall_with_walker(), config=config)
    ahead = 180  # the beam at angle 0
    _run(sim, 1.5)
    scan = sim.robot.read_scan()
    assert scan is not None and scan.stamp == 1.5
    (person,) = sim.people_poses()
    assert (person.x, person.y, person.theta) == pytest.approx((5.0, 2.0, math.pi / 2))
    assert scan.ranges[ahead] == pytest.approx(3.0 - 0.25)
    _run(sim, 1.5)  # the walker is at the north end now
    scan = sim.robot.read_scan()
    assert scan is not None
    assert scan.ranges[ahead] == pytest.approx(9.9 - 2.0)


def test_people_switched_off_are_invisible() -> None:
    config = SimConfig(lidar_range_noise=0.0, lidar_rate=10.0, person_pause=0.0)
    sim = Simulation(_hall_with_walker(), config=config, people=False)
    _run(sim, 1.5)
    scan = sim.robot.read_scan()
    assert scan is not None and scan.ranges[180] == pytest.approx(7.9)
    assert sim.people_poses() == ()
    sim.set_people(True)
    _run(sim, 0.1)
    assert len(sim.people_poses()) == 1


def test_a_person_walking_at_a_parked_robot_stops_short_of_it() -> None:
    walker = PersonRoute(((8.0, 2.0), (1.0, 2.0)), speed=1.2, loop=False)
    sim = Simulation(ascii_world(HALL, start=Pose2D(4.0, 2.0, 0.0), people=(walker,)),
                     config=QUIET)
    _run(sim, 10.0)
    (person,) = sim.people_poses()
    assert person.x == pytest.approx(4.0 + 0.5 + 0.3, abs=0.025)
    assert sim.collisions == []


def test_driving_into_a_person_is_a_person_collision() -> None:
    walker = PersonRoute(((5.0, 1.9), (5.0, 2.1)), speed=0.1, loop=False)
    sim = Simulation(ascii_world(HALL, start=Pose2D(2.0, 2.0, 0.0), people=(walker,)),
                     config=QUIET)
    sim.robot.drive(Twist(0.6, 0.0))
    for _ in range(round(8.0 / 0.02)):
        sim.step()
        circles = np.array([[p.x, p.y, 0.25] for p in sim.people_poses()])
        assert person_clearance(sim.true_pose.x, sim.true_pose.y, 0.25, circles) >= 0.0
    assert [c.obstacle for c in sim.collisions] == ["person"]


def test_same_seed_repeats_exactly_and_another_seed_differs() -> None:
    def run(seed: int) -> Simulation:
        sim = Simulation(_hall_with_walker(), seed=seed)
        sim.robot.drive(Twist(0.5, 0.3))
        _run(sim, 2.0)
        return sim

    a, b, c = run(11), run(11), run(12)
    assert a.odometry == b.odometry and a.imu == b.imu
    assert a.scan is not None and b.scan is not None and c.scan is not None
    assert np.array_equal(a.scan.ranges, b.scan.ranges)
    assert a.true_pose == c.true_pose  # the truth does not depend on the noise
    assert a.odometry.pose != c.odometry.pose
    assert not np.array_equal(a.scan.ranges, c.scan.ranges)


def test_odometry_drifts_from_the_truth_but_stays_close() -> None:
    sim = Simulation(_corridor(), seed=2)
    sim.robot.drive(Twist(0.8, 0.0))
    _run(sim, 8.0)
    error = sim.odometry_to_world(sim.odometry.pose).distance_to(sim.true_pose)
    assert sim.true_pose.x > 6.0
    assert 0.0 < error < 0.1


def test_battery_drains_faster_when_moving() -> None:
    idle, moving = Simulation(_corridor()), Simulation(_corridor())
    moving.robot.drive(Twist(1.0, 0.0))
    _run(idle, 8.0)
    _run(moving, 8.0)
    assert moving.battery.percent < idle.battery.percent < 80.0
    assert moving.battery.current < idle.battery.current < 0.0


def test_standing_on_the_charger_charges_and_leaving_stops_it() -> None:
    dock = Pose2D(2.0, 1.0, math.pi)
    world = ascii_world(CORRIDOR, start=Pose2D(2.05, 1.0, math.pi - 0.1),
                        points=(("charger", dock, PointKind.CHARGER),))
    sim = Simulation(world)
    _run(sim, 60.0)
    assert sim.robot.dock_contact() and sim.battery.charging
    assert sim.battery.percent > 80.0
    sim.robot.drive(Twist(-0.3, 0.0))
    _run(sim, 1.0)
    assert not sim.robot.dock_contact() and not sim.battery.charging


def test_teleport_changes_floor_and_pose_but_not_odometry() -> None:
    world = ascii_world(CORRIDOR, start=Pose2D(0.6, 1.0, 0.0), floors=("ground", "upper"))
    sim = Simulation(world, config=QUIET)
    sim.robot.drive(Twist(0.5, 0.0))
    _run(sim, 1.0)
    odometry = sim.odometry
    sim.teleport("upper", Pose2D(5.0, 1.0, math.pi))
    assert sim.floor == "upper"
    assert sim.true_pose == Pose2D(5.0, 1.0, math.pi)
    assert sim.true_twist == Twist()
    assert sim.odometry == odometry
    scan = sim.robot.read_scan()
    assert scan is not None and scan.stamp == sim.clock.now()
    with pytest.raises(InvalidRequest):
        sim.teleport("ground", Pose2D(0.05, 1.0, 0.0))  # in the west wall
    with pytest.raises(InvalidRequest):
        sim.teleport("attic", Pose2D(5.0, 1.0, 0.0))
    assert sim.floor == "upper" and sim.true_pose == Pose2D(5.0, 1.0, math.pi)


def test_start_in_a_wall_or_on_an_unknown_floor_is_refused() -> None:
    with pytest.raises(InvalidRequest):
        Simulation(_corridor(), pose=Pose2D(0.2, 1.0, 0.0))
    with pytest.raises(InvalidRequest):
        Simulation(_corridor(), floor="attic")


def test_another_floor_starts_at_its_initial_point() -> None:
    initial = Pose2D(3.0, 1.0, 0.5)
    world = ascii_world(CORRIDOR, start=Pose2D(0.6, 1.0, 0.0), floors=("ground", "upper"),
                        points=(("home", initial, PointKind.INITIAL),))
    sim = Simulation(world, floor="upper")
    assert (sim.floor, sim.true_pose) == ("upper", initial)
