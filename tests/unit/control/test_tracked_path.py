from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.control.tracked_path import TrackedPath

L_PATH = TrackedPath.from_points([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0]])


def test_arc_lengths_and_repeated_points_dropped() -> None:
    path = TrackedPath.from_points([[0.0, 0.0], [0.0, 0.0], [3.0, 4.0], [3.0, 4.0], [3.0, 5.0]])
    assert path.points.tolist() == [[0.0, 0.0], [3.0, 4.0], [3.0, 5.0]]
    assert path.cumulative.tolist() == [0.0, 5.0, 6.0]
    assert path.length == 6.0
    assert path.end == (3.0, 5.0)


def test_empty_path_is_refused() -> None:
    with pytest.raises(ValueError, match="at least one point"):
        TrackedPath.from_points(np.zeros((0, 2)))


def test_points_at_interpolates_and_clamps() -> None:
    pts = L_PATH.points_at(np.array([-1.0, 0.5, 2.0, 3.5, 9.0]))
    assert pts.tolist() == [[0.0, 0.0], [0.5, 0.0], [2.0, 0.0], [2.0, 1.5], [2.0, 2.0]]
    assert L_PATH.point_at(1.25) == (1.25, 0.0)


def test_project_finds_the_nearest_point_on_a_segment_not_a_vertex() -> None:
    sparse = TrackedPath.from_points([[0.0, 0.0], [10.0, 0.0]])
    assert sparse.project(3.3, 0.4, start=0.0, window=20.0) == pytest.approx(3.3)


def test_project_never_goes_back() -> None:
    assert L_PATH.project(0.5, 0.1, start=1.0, window=2.0) == 1.0


def test_project_searches_only_the_window() -> None:
    # The robot stands next to the second leg, but the window ends on the first one.
    assert L_PATH.project(2.1, 1.5, start=0.0, window=1.0) == 1.0
    assert L_PATH.project(2.1, 1.5, start=0.0, window=5.0) == pytest.approx(3.5)


def test_project_tells_overlapping_legs_of_a_hairpin_apart_by_heading() -> None:
    hairpin = TrackedPath.from_points([[0.0, 0.0], [3.0, 0.0], [0.0, 0.0]])
    assert hairpin.project(2.0, 0.0, start=1.5, window=5.0, heading=0.0) == pytest.approx(2.0)
    assert hairpin.project(2.0, 0.0, start=1.5, window=5.0, heading=math.pi) == pytest.approx(4.0)
    assert hairpin.project(2.0, 0.0, start=1.5, window=5.0) == pytest.approx(2.0)


def test_lookahead_is_where_the_path_leaves_the_circle() -> None:
    # Robot 0.3 m beside the first leg, radius 0.5: the crossing is 0.4 m ahead along x.
    carrot = L_PATH.lookahead(0.0, 0.3, start=0.0, radius=0.5, window=3.0)
    assert carrot == pytest.approx((0.4, 0.0))


def test_lookahead_goes_round_the_corner() -> None:
    carrot = L_PATH.lookahead(1.8, 0.0, start=1.8, radius=0.5, window=3.0)
    assert carrot is not None
    assert carrot[0] == 2.0
    assert carrot[1] == pytest.approx(math.sqrt(0.5**2 - 0.2**2))


def test_lookahead_is_none_when_the_rest_of_the_path_is_inside_the_circle() -> None:
    assert L_PATH.lookahead(2.0, 1.7, start=3.7, radius=0.5, window=3.0) is None


def test_lookahead_steers_back_to_the_path_when_the_robot_is_far_off_it() -> None:
    assert L_PATH.lookahead(1.0, 1.0, start=1.0, radius=0.5, window=3.0) == (1.0, 0.0)


def test_lookahead_inside_a_winding_window_returns_the_last_point_searched() -> None:
    zigzag = TrackedPath.from_points([[0.0, 0.0], [0.1, 0.1], [0.0, 0.2], [0.1, 0.3], [5.0, 0.3]])
    carrot = zigzag.lookahead(0.0, 0.0, start=0.0, radius=1.0, window=0.3)
    assert carrot == (0.1, 0.3)


def test_single_point_path() -> None:
    point = TrackedPath.from_points([[1.0, 1.0]])
    assert point.length == 0.0
    assert point.project(0.0, 0.0, start=0.0, window=1.0) == 0.0
    assert point.lookahead(0.0, 0.0, start=0.0, radius=0.5, window=1.0) == (1.0, 1.0)
    assert point.lookahead(0.9, 1.0, start=0.0, radius=0.5, window=1.0) is None


def test_poses_at_are_the_points_and_the_headings_of_their_segments() -> None:
    s = np.array([-1.0, 0.5, 2.0, 3.5, 9.0])
    poses = L_PATH.poses_at(s)
    assert poses[:, :2].tolist() == L_PATH.points_at(s).tolist()
    assert poses[:, 2].tolist() == L_PATH.headings_at(s).tolist()
    assert poses[:, 2].tolist() == pytest.approx([0.0, 0.0, math.pi / 2, math.pi / 2, math.pi / 2])
    point = TrackedPath.from_points([[1.0, 2.0]])
    assert point.poses_at(np.array([0.0, 3.0])).tolist() == [[1.0, 2.0, 0.0], [1.0, 2.0, 0.0]]


def test_project_with_a_window_before_the_path_answers_its_start() -> None:
    # A window wholly before the first point still holds the first segment.
    assert L_PATH.project(0.5, 0.3, start=-3.0, window=1.0) == 0.0


def test_project_picks_the_first_of_equally_near_stretches_without_a_heading() -> None:
    # Two parallel legs 0.04 m either side of the robot: nearest first, then by heading.
    u_turn = TrackedPath.from_points([[0.0, 0.02], [2.0, 0.02], [2.0, -0.02], [0.0, -0.02]])
    assert u_turn.project(1.0, 0.0, start=0.0, window=5.0) == pytest.approx(1.0)
    back = u_turn.project(1.0, 0.0, start=0.0, window=5.0, heading=math.pi)
    assert back == pytest.approx(2.04 + 1.0)
