"""People in the way, on simulated time with the whole stack: the robot waits for a person in
the only door, passes when they walk away, and gives up with ``blocked by person`` only after
its patience when they never do.

The world is built here: two 6 m x 6 m rooms joined by one door 1 m wide, the robot in the west
room, its goal in the east one, a walker standing in the door.
"""

from __future__ import annotations

import numpy as np
import pytest

from polynav.geometry import Pose2D
from polynav.maps.map import Map, MapInfo
from polynav.nav import events
from polynav.nav.attempt import FailureReason, NavigationState
from polynav.nav.people import PeopleConfig
from polynav.nav.stack import StackConfig
from polynav.robot.sim.config import SimConfig
from polynav.runtime.sim_driver import SimDriver, simulate
from polynav.worlds.world import PersonRoute, World, WorldFloor

RES = 0.05
DOOR = (6.0, 3.0)
START = Pose2D(2.5, 3.0, 0.0)
GOAL = Pose2D(9.5, 3.0, 0.0)


def _two_rooms(
    person: PersonRoute,
    *,
    depth: float = 6.0,
    doors: tuple[float, ...] = (DOOR[1],),
    furniture: tuple[tuple[float, float], ...] = ((1.0, 1.0), (4.5, 5.0), (8.0, 1.2), (10.8, 4.6)),
) -> World:
    """Two rooms 6 m wide and ``depth`` deep, joined by doors 1 m wide at heights ``doors`` in
    the wall between them, with the furniture that pins the scan down along both walls of each
    room."""
    width, height = int(12.0 / RES), int(depth / RES)
    data = np.zeros((height, width), dtype=np.int8)
    wall = 4  # cells: 0.2 m walls
    data[:wall, :] = data[-wall:, :] = 100
    data[:, :wall] = data[:, -wall:] = 100
    mid = int(DOOR[0] / RES)
    data[:, mid - 2: mid + 2] = 100
    for y in doors:
        data[int((y - 0.5) / RES): int((y + 0.5) / RES), mid - 2: mid + 2] = 0
    for x, y in furniture:
        ix, iy = int(x / RES), int(y / RES)
        data[iy - 6: iy + 6, ix - 6: ix + 6] = 100
    grid = Map(MapInfo(RES, width, height, Pose2D(0.0, 0.0, 0.0)), data)
    floor = WorldFloor("f", 1, "f", grid, (), None, (person,))
    return World("two_rooms", (floor,), "f", START)


def _drive(person: PersonRoute, *, patience: float, pause: float) -> tuple[SimDriver, list]:
    seen: list[events.NavigationEvent] = []
    driver = simulate(
        _two_rooms(person),
        seed=3,
        sim_config=SimConfig(person_pause=pause),
        stack_config=StackConfig(people=PeopleConfig(patience=patience)),
        on_event=seen.append,
    )
    driver.stack.go_to(GOAL, driver.now)
    assert driver.run_until(lambda: driver.stack.navigator.state.finished, timeout=200.0)
    return driver, seen


def _first(seen: list, kind: type) -> events.NavigationEvent:
    return next(e for e in seen if isinstance(e, kind))


def test_waits_for_a_person_in_the_door_and_passes_when_they_walk_away() -> None:
    # The walker comes out of the east room's corner into the door (at 3.5 s), stands there
    # 20 s, then walks back to the corner.
    person = PersonRoute(((6.8, 5.0), DOOR), speed=0.6, loop=False)
    driver, seen = _drive(person, patience=60.0, pause=20.0)
    attempt = driver.stack.navigator.attempt
    assert attempt is not None and attempt.state is NavigationState.SUCCEEDED, attempt
    assert driver.sim.true_pose.distance_to(GOAL) <= 0.1
    waiting = _first(seen, events.NavigationWaiting)
    assert waiting.cause == "person"
    assert sum(isinstance(e, events.NavigationWaiting) for e in seen) == 1
    assert attempt.ended_at is not None and attempt.ended_at > 23.5  # it went after they left
    assert driver.sim.collisions == []


def test_gives_up_with_blocked_by_person_after_the_patience_only() -> None:
    person = PersonRoute((DOOR, DOOR), speed=0.6)  # stands in the door for good
    driver, seen = _drive(person, patience=25.0, pause=2.0)
    attempt = driver.stack.navigator.attempt
    assert attempt is not None and attempt.state is NavigationState.FAILED
    assert attempt.reason is FailureReason.BLOCKED_BY_PERSON
    waiting = _first(seen, events.NavigationWaiting)
    assert attempt.ended_at is not None
    assert attempt.ended_at - waiting.stamp == pytest.approx(25.0, abs=0.2)
    assert driver.sim.true_pose.x < DOOR[0]  # it never pushed through
    assert driver.sim.collisions == []


def _two_doors(person: PersonRoute) -> World:
    """The two rooms 12 m deep, joined by the near door (y = 3 m) and a far one (y = 11 m): the
    way through the far door is 10 m longer."""
    return _two_rooms(
        person, depth=12.0, doors=(DOOR[1], 11.0),
        furniture=((1.0, 1.0), (4.5, 5.0), (1.5, 8.5), (8.0, 1.2), (10.8, 4.6), (9.5, 9.0)),
    )


def test_takes_the_near_door_again_once_the_person_in_it_walks_on() -> None:
    # The walker stands in the near door from 3.5 s to 11.5 s. The robot sets off the long way
    # round through the far door; once the walker has gone, the whole way is planned again at the
    # next re-plan and the robot turns back, rather than keep to the long way for up to the full
    # re-plan period.
    person = PersonRoute(((6.8, 5.0), DOOR), speed=0.6, loop=False)
    driver = simulate(
        _two_doors(person), seed=3, sim_config=SimConfig(person_pause=8.0),
        stack_config=StackConfig(people=PeopleConfig(patience=60.0)),
    )
    driver.stack.go_to(GOAL, driver.now)
    farthest = 0.0

    def done() -> bool:
        nonlocal farthest
        farthest = max(farthest, driver.sim.true_pose.y)
        return driver.stack.navigator.state.finished

    assert driver.run_until(done, timeout=120.0)
    attempt = driver.stack.navigator.attempt
    assert attempt is not None and attempt.state is NavigationState.SUCCEEDED, attempt
    assert farthest < 8.0, farthest  # never through the far door
    assert driver.sim.collisions == []
