"""Keeping the social distance: the robot eases to a stop at the edge of a person's space
instead of closing in, follows someone walking away at their pace, and a robot held that way
hands over to the wait (re-plans, giving way); stepping aside never brushes anyone."""

from __future__ import annotations

import math

import pytest

from polynav.geometry import Pose2D, Twist
from polynav.nav.people import PeopleConfig, PeopleView, Person, aside_spots
from polynav.nav.people_wait import PeopleWait
from tests.unit.nav.test_navigator import (
    FakeCostmap,
    Harness,
    ScriptedController,
    ScriptedPlanner,
)

CFG = PeopleConfig()


def _wait(*people: Person) -> PeopleWait:
    wait = PeopleWait(CFG, FakeCostmap(), ScriptedPlanner(), ScriptedController(),  # type: ignore[arg-type]
                      robot_radius=0.25)
    wait.people = PeopleView(people)
    return wait


@pytest.mark.parametrize("distance", [0.85, 1.0, 1.2])
def test_speed_towards_a_person_falls_to_nothing_at_the_social_distance(distance: float) -> None:
    wait = _wait(Person(distance, 0.0))
    twist = wait.slow(Pose2D(), Twist(0.6, 0.0))
    allowed = (distance - CFG.social_distance) / CFG.approach_time
    assert twist.linear == pytest.approx(min(0.6, allowed))


def test_no_closing_in_within_the_social_distance_but_moving_away_is_free() -> None:
    wait = _wait(Person(0.7, 0.0))
    assert wait.slow(Pose2D(), Twist(0.5, 0.2)) == Twist(0.0, 0.0)
    # Away from them (backing off), only the slow speed applies.
    assert wait.slow(Pose2D(), Twist(-0.5, 0.0)).linear == pytest.approx(-CFG.slow_speed)
    # Facing away from them, forwards.
    assert wait.slow(Pose2D(0.0, 0.0, math.pi), Twist(0.5, 0.0)).linear == pytest.approx(
        CFG.slow_speed)


def test_passing_beside_someone_is_slowed_not_stopped() -> None:
    wait = _wait(Person(0.0, 1.0))  # abeam, 1 m to the left: driving on does not close in
    assert wait.slow(Pose2D(), Twist(0.6, 0.0)).linear == pytest.approx(0.6)


def test_follows_someone_walking_away_at_their_pace() -> None:
    wait = _wait(Person(0.8, 0.0, vx=0.4))  # at the edge of their space, walking on at 0.4
    assert wait.slow(Pose2D(), Twist(0.6, 0.0)).linear == pytest.approx(0.4)


def test_the_same_curvature_is_kept() -> None:
    wait = _wait(Person(1.0, 0.0))
    twist = wait.slow(Pose2D(), Twist(0.6, 0.6))
    assert twist.angular / twist.linear == pytest.approx(1.0)


def test_a_robot_held_by_people_waits_for_them() -> None:
    h = Harness(ScriptedPlanner(), ScriptedController())
    h.nav.start(Pose2D(5.0, 0.0, 0.0), h.now)
    h.people = PeopleView((Person(0.75, 0.0),))  # right in front, inside their space
    h.run(CFG.hold_before_wait - 0.1)
    assert h.twists[-1].linear == 0.0 and "NavigationWaiting" not in h.kinds()
    h.run(0.3)
    assert h.kinds().count("NavigationWaiting") == 1


def test_stepping_aside_never_leads_nearer_anyone() -> None:
    pose = Pose2D(0.0, 0.0, 0.0)
    people = PeopleView((Person(0.7, 0.3), Person(-0.9, 0.0)))
    spots = aside_spots(FakeCostmap(), pose, people, CFG, limit=50)  # type: ignore[arg-type]
    assert spots
    for spot in spots:
        for p in people.people:
            now = math.hypot(p.x, p.y)
            for t in (0.25, 0.5, 0.75, 1.0):
                x, y = spot.x * t, spot.y * t
                assert math.hypot(p.x - x, p.y - y) >= min(now, CFG.social_distance) - 1e-6
