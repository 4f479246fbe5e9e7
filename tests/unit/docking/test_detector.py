"""The dock detector on synthetic scans: a plate with a notch ray-cast exactly, with noise,
clutter, a partial view, and shapes that are not a dock."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
import pytest

from polynav.docking.detector import DetectorConfig, find_dock, points_of_scan, refine_dock
from polynav.docking.shape import DockShape, docked_at, face_of, world_segments
from polynav.errors import ConfigError
from polynav.geometry import Pose2D, angle_diff
from polynav.robot.interface import LaserScan
from polynav.robot.sim.charger import segment_ranges

SHAPE = DockShape()
FACE = Pose2D(3.0, 2.0, math.radians(20.0))  # the true plate
BEAMS = 360


def _wall_behind(face: Pose2D, gap: float = 0.3, half: float = 2.0) -> npt.NDArray[np.float64]:
    """A wall ``gap`` behind the face, across it."""
    c, s = math.cos(face.theta), math.sin(face.theta)
    bx, by = face.x + gap * c, face.y + gap * s
    return np.array([[bx + half * s, by - half * c, bx - half * s, by + half * c]])


def _scan(robot: Pose2D, segments: npt.NDArray[np.float64], *, noise: float = 0.0,
          seed: int = 0, fov: float = 2.0 * math.pi) -> LaserScan:
    angles = -0.5 * fov + fov * np.arange(BEAMS) / BEAMS
    ranges = segment_ranges(robot.x, robot.y, angles + robot.theta, segments, 12.0)
    ranges = ranges + noise * np.random.default_rng(seed).standard_normal(BEAMS)
    return LaserScan(stamp=0.0, angle_min=float(angles[0]), angle_increment=fov / BEAMS,
                     range_min=0.05, range_max=12.0, ranges=ranges.astype(np.float32))


def _robot_in_front(face: Pose2D, distance: float = 0.75, lateral: float = 0.0,
                    turn: float = 0.0) -> Pose2D:
    return face.compose(Pose2D(-distance, lateral, turn))


def _points(robot: Pose2D, segments: npt.NDArray[np.float64], **kw: float) -> npt.NDArray[
        np.float64]:
    return points_of_scan(_scan(robot, segments, **kw), robot)  # type: ignore[arg-type]


def _off(found: Pose2D, truth: Pose2D) -> tuple[float, float]:
    return found.distance_to(truth), abs(angle_diff(found.theta, truth.theta))


def test_finds_the_plate_10_cm_and_5_degrees_off_the_marker_with_noise() -> None:
    segments = np.concatenate((world_segments(FACE, SHAPE), _wall_behind(FACE)))
    marker = FACE.compose(Pose2D(-0.06, 0.08, math.radians(5.0)))
    robot = _robot_in_front(marker)
    for seed in range(5):
        found = find_dock(_points(robot, segments, noise=0.01, seed=seed), marker, SHAPE)
        assert found is not None
        position, heading = _off(found.pose, FACE)
        assert position < 0.015 and heading < math.radians(2.0), (seed, found)
        assert found.quality > 0.9 and found.residual < 0.02


def test_tracking_from_the_last_pose_follows_the_robot_in() -> None:
    segments = world_segments(FACE, SHAPE)
    guess = FACE.compose(Pose2D(0.02, -0.02, 0.03))
    for distance in (0.7, 0.5, 0.3, 0.1):
        robot = _robot_in_front(FACE, distance, lateral=0.02)
        found = refine_dock(_points(robot, segments, noise=0.005), guess, SHAPE)
        assert found is not None
        position, heading = _off(found.pose, FACE)
        assert position < 0.01 and heading < math.radians(1.5)
        guess = found.pose


def test_clutter_beside_the_plate_does_not_move_it() -> None:
    c, s = math.cos(FACE.theta), math.sin(FACE.theta)
    box = []  # a box's front 0.45 m to the plate's left, a little nearer the robot
    for lateral in (0.45, 0.75):
        bx, by = FACE.x - 0.1 * c - lateral * s, FACE.y - 0.1 * s + lateral * c
        box.append((bx, by))
    clutter = np.array([[box[0][0], box[0][1], box[1][0], box[1][1]]])
    segments = np.concatenate((world_segments(FACE, SHAPE), _wall_behind(FACE), clutter))
    found = find_dock(_points(_robot_in_front(FACE, 0.8, 0.1), segments, noise=0.01),
                      FACE.compose(Pose2D(0.05, -0.05, -0.05)), SHAPE)
    assert found is not None
    position, heading = _off(found.pose, FACE)
    assert position < 0.015 and heading < math.radians(2.0)


def test_a_partial_view_with_one_wing_hidden_still_finds_it() -> None:
    segments = world_segments(FACE, SHAPE)[:3]  # the left wing is not seen
    found = find_dock(_points(_robot_in_front(FACE), segments, noise=0.005),
                      FACE.compose(Pose2D(0.0, 0.05, 0.05)), SHAPE)
    assert found is not None
    assert _off(found.pose, FACE)[0] < 0.015


@pytest.mark.parametrize("what", ["flat wall", "round post", "nothing", "wide notch"])
def test_shapes_that_are_not_a_dock_are_none(what: str) -> None:
    robot = _robot_in_front(FACE)
    if what == "flat wall":
        segments = _wall_behind(FACE, gap=0.0)
    elif what == "round post":
        k = np.arange(33)
        ring = np.stack((FACE.x + 0.2 * np.cos(k * 2 * math.pi / 32),
                         FACE.y + 0.2 * np.sin(k * 2 * math.pi / 32)), axis=1)
        segments = np.concatenate((ring[:-1], ring[1:]), axis=1)
    elif what == "nothing":
        segments = np.zeros((0, 4))
    else:  # a gap in a wall, 0.6 m wide, 0.3 m deep: a doorway's reveal, not the notch
        segments = world_segments(FACE, DockShape(width=1.4, notch_width=0.9, notch_depth=0.4))
    assert find_dock(_points(robot, segments, noise=0.01), FACE, SHAPE) is None


def test_the_plate_far_from_the_marker_is_not_taken() -> None:
    segments = world_segments(FACE, SHAPE)
    marker = FACE.compose(Pose2D(0.0, 0.6, 0.0))  # another charger's place
    assert find_dock(_points(_robot_in_front(marker), segments), marker, SHAPE) is None


def test_docked_and_face_poses_are_inverse() -> None:
    docked = Pose2D(1.0, 2.0, 0.4)
    back = docked_at(face_of(docked, 0.25), 0.25)
    assert back.distance_to(docked) < 1e-12 and abs(back.theta - docked.theta) < 1e-12


def test_bad_shapes_and_settings_are_refused() -> None:
    with pytest.raises(ConfigError, match="notch_width"):
        DockShape(width=0.3, notch_width=0.4)
    with pytest.raises(ConfigError, match="notch_depth"):
        DockShape(notch_depth=0.0)
    with pytest.raises(ConfigError, match="min_quality"):
        DetectorConfig(min_quality=1.5)
