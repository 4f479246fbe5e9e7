from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.robot.sim.people import Person, as_circles
from polynav.worlds.world import PersonRoute

DT = 0.02


def _walk(person: Person, seconds: float, robot: tuple[float, float, float] | None = None
          ) -> None:
    for _ in range(round(seconds / DT)):
        person.step(DT, robot)


def test_back_and_forth_route_pauses_at_the_far_end_and_walks_back() -> None:
    person = Person(PersonRoute(((0.0, 0.0), (4.0, 0.0)), speed=1.0, loop=False),
                    pause=2.0, stop_distance=0.3)
    _walk(person, 3.0)
    assert (person.x, person.y) == pytest.approx((3.0, 0.0))
    assert person.heading == 0.0
    _walk(person, 2.0)  # 1 s to the end, then 1 s of the pause
    assert person.x == pytest.approx(4.0)
    _walk(person, 1.0)  # the rest of the pause
    assert person.x == pytest.approx(4.0)
    _walk(person, 1.0)
    assert person.x == pytest.approx(3.0)
    assert person.heading == pytest.approx(math.pi)


def test_loop_route_goes_round_the_circuit() -> None:
    person = Person(PersonRoute(((0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)), speed=0.5),
                    pause=0.0, stop_distance=0.3)
    _walk(person, 6.0)  # 3 m: the first side and half the second
    assert (person.x, person.y) == pytest.approx((2.0, 1.0))
    assert person.heading == pytest.approx(math.pi / 2)
    _walk(person, 10.0)  # 5 m more: the whole 8 m circuit
    assert (person.x, person.y) == pytest.approx((0.0, 0.0), abs=1e-9)


def test_person_stops_short_of_a_robot_in_front_and_walks_on_when_it_leaves() -> None:
    person = Person(PersonRoute(((0.0, 0.0), (4.0, 0.0)), speed=1.0, loop=False),
                    pause=0.0, stop_distance=0.3)
    robot = (1.0, 0.1, 0.25)
    _walk(person, 5.0, robot)
    # Contact would come at x = 1.0 - sqrt(0.5² - 0.1²); the person waits 0.3 m before it.
    contact = 1.0 - math.sqrt(0.25 - 0.01)
    assert contact - 0.3 - DT <= person.x <= contact - 0.3
    _walk(person, 1.0, None)
    assert person.x > contact


def test_person_held_up_past_their_patience_turns_round_and_walks_the_route_back() -> None:
    person = Person(PersonRoute(((0.0, 0.0), (4.0, 0.0)), speed=1.0, loop=False),
                    pause=0.0, stop_distance=0.3, patience=3.0)
    robot = (2.0, 0.0, 0.25)
    _walk(person, 2.0, robot)  # reaches 2.0 - 0.5 - 0.3 = 1.2 m at 1.2 s, then waits
    held_at = person.x
    assert held_at == pytest.approx(1.2, abs=DT)
    _walk(person, 2.5, robot)  # 0.8 s waited, then 3 s more: turns round at 4.2 s
    assert person.x == pytest.approx(held_at - 0.3, abs=3 * DT)
    assert math.cos(person.heading) == pytest.approx(-1.0)
    _walk(person, 3.0, robot)  # back to the start of the route, and on: held up again
    assert person.x == pytest.approx(held_at, abs=DT)
    assert person.heading == 0.0


def test_loop_walker_turns_round_onto_the_circuit_the_other_way() -> None:
    person = Person(PersonRoute(((0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)), speed=0.5),
                    pause=0.0, stop_distance=0.3, patience=1.0)
    _walk(person, 2.0)  # 1 m along the first side
    _walk(person, 1.1, (1.6, 0.0, 0.25))  # held at once, turns round
    assert math.cos(person.heading) == pytest.approx(-1.0)
    _walk(person, 4.0)  # (0.05 m back already) 0.95 m to the corner, on up the west side
    assert (person.x, person.y) == pytest.approx((0.0, 1.05), abs=0.02)
    assert person.heading == pytest.approx(math.pi / 2)


@pytest.mark.parametrize("robot", [(1.0, 0.5, 0.25), (-0.6, 0.0, 0.25)])
def test_person_walks_past_a_robot_beside_or_behind(robot: tuple[float, float, float]) -> None:
    person = Person(PersonRoute(((0.0, 0.0), (4.0, 0.0)), speed=1.0, loop=False),
                    pause=0.0, stop_distance=0.3)
    _walk(person, 2.0, robot)
    assert person.x == pytest.approx(2.0)


def test_people_as_circles() -> None:
    a = Person(PersonRoute(((1.0, 2.0), (3.0, 2.0)), speed=1.0, radius=0.3), pause=0.0,
               stop_distance=0.3)
    assert np.array_equal(as_circles([a]), np.array([[1.0, 2.0, 0.3]]))
    assert as_circles([]).shape == (0, 3)
