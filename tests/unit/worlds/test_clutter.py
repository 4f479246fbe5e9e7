"""Clutter courses: kinds by name, the ``posts`` kind as it always was, the ``lattice`` kind's
guarantee and what it is built to hold (tight gaps, pockets open towards the start)."""

from __future__ import annotations

import hashlib
import math

import numpy as np
import pytest

from polynav import footprint as body
from polynav.errors import InvalidRequest
from polynav.footprint import Footprint
from polynav.geometry import Pose2D
from polynav.maps import costs
from polynav.maps.costmap import Costmap
from polynav.robot.profile import load_profile
from polynav.worlds.clutter import KINDS, ClutterCourse, ClutterSpec, check, draw
from polynav.worlds.clutter_course import clearance_along, sample_polyline, static_config

PROFILES = ("research-base", "demo", "delivery")


def _footprint(name: str) -> Footprint:
    return load_profile(name).footprint


def _lattice(name: str, density: float, seed: int) -> ClutterCourse:
    return draw(_footprint(name), ClutterSpec(kind="lattice", density=density), seed)


def _grid_digest(course: ClutterCourse) -> str:
    return hashlib.sha256(course.world.floors[0].map.data.tobytes()).hexdigest()[:16]


def test_kinds_are_posts_and_lattice_and_posts_is_the_default() -> None:
    assert sorted(KINDS) == ["lattice", "posts"]
    assert ClutterSpec().kind == "posts"


def test_unknown_kind_is_an_invalid_request() -> None:
    with pytest.raises(InvalidRequest) as err:
        draw(_footprint("demo"), ClutterSpec(kind="forest"), 0)
    assert err.value.field == "kind"


@pytest.mark.parametrize(
    ("name", "density", "seed", "digest", "posts"),
    [("demo", 0.0, 0, "7e1858d1080f9baa", 6), ("research-base", 1.0, 99, "de9e0f9b0abce458", 56)],
)
def test_posts_kind_draws_the_same_courses_as_before_the_kinds(
    name: str, density: float, seed: int, digest: str, posts: int
) -> None:
    # Digests of the grids drawn by the posts generator before lattice existed.
    course = draw(_footprint(name), ClutterSpec(density=density), seed)
    assert course.kind == "posts"
    assert course.posts.shape == (posts, 2)
    assert _grid_digest(course) == digest


def test_pitch_wider_than_two_post_radii_is_refused() -> None:
    with pytest.raises(InvalidRequest) as err:
        ClutterSpec(kind="lattice", pitch=0.15, post_radius=0.06)
    assert err.value.field == "pitch"


def test_short_narrow_lattice_course_still_keeps_its_way() -> None:
    footprint = _footprint("research-base")
    spec = ClutterSpec(kind="lattice", density=1.0, span=6.0, width=4.0)
    course = draw(footprint, spec, 1)
    assert course.way is not None
    assert check(course, footprint) is None
    assert bool(np.all(np.diff(course.way[:, 0]) >= 0.0))  # it never runs back


def test_same_seed_draws_the_same_lattice_course() -> None:
    a = _lattice("research-base", 0.5, 7)
    b = _lattice("research-base", 0.5, 7)
    assert _grid_digest(a) == _grid_digest(b)
    assert np.array_equal(a.posts, b.posts)
    assert a.way is not None and b.way is not None
    assert np.array_equal(a.way, b.way)
    assert a.structures == b.structures
    assert a.gaps == b.gaps
    assert _grid_digest(_lattice("research-base", 0.5, 8)) != _grid_digest(a)


@pytest.mark.parametrize("name", PROFILES)
@pytest.mark.parametrize("density", [0.0, 0.5, 1.0])
def test_lattice_way_clears_the_body_at_any_heading(name: str, density: float) -> None:
    footprint = _footprint(name)
    course = _lattice(name, density, 3)
    way = course.way
    assert way is not None
    assert course.way_clearance >= max(0.45, footprint.circumscribed_radius)
    assert clearance_along(course.world.floors[0].map, way) >= course.way_clearance
    assert check(course, footprint) is None
    assert bool(np.all(np.diff(way[:, 0]) >= 0.0))  # it winds across, never back
    # Independently of the clearance figure: the body swept along the way facing along it,
    # and turned a full circle every half metre, touches nothing.
    static = Costmap.from_map(course.world.floors[0].map, static_config(footprint))
    points = sample_polyline(way, 0.025)
    heading = np.arctan2(np.gradient(points[:, 1]), np.gradient(points[:, 0]))
    along = np.column_stack((points, heading))
    assert body.first_collision(footprint, static, along) is None
    for x, y in sample_polyline(way, 0.5):
        turn = body.rotation_poses(footprint, Pose2D(float(x), float(y), 0.0), 2.0 * math.pi,
                                   static.info.resolution)
        assert body.first_collision(footprint, static, turn) is None


def test_lattice_way_winds_off_the_straight_line() -> None:
    course = _lattice("research-base", 0.5, 11)
    assert course.way is not None
    assert float(np.max(np.abs(course.way[:, 1] - course.start.y))) >= 1.5


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_lattice_course_has_a_tight_gap_on_the_line_and_a_pocket_facing_the_start(
    seed: int,
) -> None:
    footprint = _footprint("research-base")
    course = _lattice("research-base", 1.0, seed)
    width, diagonal = 2 * footprint.inscribed_radius, 2 * footprint.circumscribed_radius
    tight = [g for g in course.gaps if width < g.width < diagonal]
    assert any(g.on_line for g in tight)
    # The planner, inflating by the inscribed radius, sees each tight gap open, but the body
    # cannot turn in it: its swept circle touches the sides.
    static = Costmap.from_map(course.world.floors[0].map, static_config(footprint))
    sweep = Footprint.circle(footprint.circumscribed_radius)
    for g in tight:
        across = np.array([math.cos(g.across), math.sin(g.across)])
        near = [np.array([g.x, g.y]) + k * 0.05 * across for k in range(-2, 3)]
        assert min(static.cost_at(float(p[0]), float(p[1])) for p in near) < costs.INSCRIBED
        assert body.collides(sweep, static, Pose2D(g.x, g.y, 0.0))
    pockets = [s for s in course.structures if s.kind == "pocket"]
    assert any(
        (course.start.x - s.x) * math.cos(s.facing) + (course.start.y - s.y) * math.sin(s.facing)
        > 0.0
        for s in pockets
    )


def test_lattice_optimal_length_is_a_lower_bound_of_the_way() -> None:
    course = _lattice("research-base", 1.0, 5)
    assert course.way is not None
    way_length = float(np.sum(np.hypot(*np.diff(course.way, axis=0).T)))
    straight = math.hypot(course.goal.x - course.start.x, course.goal.y - course.start.y)
    assert straight - 1e-9 <= course.optimal_length <= way_length


def test_a_course_whose_way_touches_a_post_fails_the_check() -> None:
    footprint = _footprint("research-base")
    course = _lattice("research-base", 0.5, 4)
    assert course.way is not None
    # Lay the way straight through the obstacles: it no longer keeps its clearance.
    straight = np.array([[course.start.x, course.start.y], [course.goal.x, course.goal.y]])
    bent = ClutterCourse(course.world, course.start, course.goal, course.posts, course.min_gap,
                         course.path, kind="lattice", way=straight,
                         way_clearance=course.way_clearance)
    problem = check(bent, footprint)
    assert problem is not None and "passes" in problem
