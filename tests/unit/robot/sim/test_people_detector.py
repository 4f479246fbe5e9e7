from __future__ import annotations

import math

import numpy as np

from polynav.geometry import Pose2D
from polynav.maps.map import MapInfo
from polynav.robot.sim.people_detector import PeopleDetector

INFO = MapInfo(resolution=0.1, width=100, height=100, origin=Pose2D(0.0, 0.0, 0.0))


def _walled() -> np.ndarray:
    occupied = np.zeros((100, 100), dtype=bool)
    occupied[:, 50] = True  # a wall along x = 5 m
    return occupied


def test_people_behind_a_wall_or_out_of_range_are_not_seen() -> None:
    detector = PeopleDetector(max_range=4.0, fov=2.0 * math.pi)
    robot = Pose2D(2.0, 5.0, 0.0)
    seen = detector.detect(0.0, robot, [(4.0, 5.0), (7.0, 5.0), (2.0, 9.5)], _walled(), INFO)
    assert [(d.x, d.y) for d in seen] == [(2.0, 0.0)]  # the one in the room, 2 m ahead


def test_positions_and_velocities_are_in_the_robot_frame_and_ids_are_stable() -> None:
    detector = PeopleDetector(max_range=10.0, fov=2.0 * math.pi)
    robot = Pose2D(2.0, 2.0, math.pi / 2)  # facing +y
    free = np.zeros((100, 100), dtype=bool)
    first = detector.detect(0.0, robot, [(2.0, 4.0)], free, INFO)
    second = detector.detect(0.5, robot, [(2.5, 4.0)], free, INFO)  # walked 1 m/s along +x
    assert first[0].track_id == second[0].track_id
    d = second[0]
    assert math.isclose(d.x, 2.0, abs_tol=1e-9) and math.isclose(d.y, -0.5, abs_tol=1e-9)
    # +x in the map is to the robot's right (-y) when it faces +y.
    assert math.isclose(d.vx, 0.0, abs_tol=1e-9) and math.isclose(d.vy, -1.0, abs_tol=1e-9)


def test_a_person_who_reappears_gets_a_new_track_and_the_fov_limits_sight() -> None:
    detector = PeopleDetector(max_range=10.0, fov=math.pi)  # the front half only
    robot = Pose2D(2.0, 5.0, 0.0)
    walled = _walled()
    one = detector.detect(0.0, robot, [(4.0, 5.0)], walled, INFO)
    assert detector.detect(1.0, robot, [(6.0, 5.0)], walled, INFO) == []  # behind the wall
    again = detector.detect(2.0, robot, [(4.0, 5.5)], walled, INFO)
    assert again[0].track_id != one[0].track_id
    assert detector.detect(3.0, robot, [(1.0, 5.0)], walled, INFO) == []  # behind the robot
