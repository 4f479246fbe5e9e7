"""Stepping aside for a walker keeps their space: the spot and the way to it are judged
against where the walker will be, not only where they are, and while stepping aside the robot
never drives at someone inside their space, yet keeps turning off their way instead of
standing face to face."""

from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.geometry import Pose2D, Twist
from polynav.maps import costs
from polynav.nav.people import PeopleConfig, PeopleView, Person, aside_spots
from polynav.nav.people_wait import PeopleWait
from polynav.planning.path import Path
from tests.unit.nav.test_navigator import FakeCostmap, ScriptedController, ScriptedPlanner

CFG = PeopleConfig()


class _Corridor:
    """A 3 m wide corridor along x (cost_at as a costmap answers it)."""

    def cost_at(self, x: float, y: float) -> int:
        return costs.FREE if 0.2 <= y <= 2.8 else costs.LETHAL


def _side(walker: Person, x: float, y: float) -> float:
    speed = math.hypot(walker.vx, walker.vy)
    return (walker.vx * (y - walker.y) - walker.vy * (x - walker.x)) / speed


def _closes_in_on(walker: Person, robot: Pose2D, spot: Pose2D) -> float:
    """The closest the robot gets to the walker while closing in on them, on a straight way to
    ``spot`` at the slow speed (right away, the least time the walker has to come near)."""
    length = spot.distance_to(robot)
    ux, uy = (spot.x - robot.x) / length, (spot.y - robot.y) / length
    closest = math.inf
    for k in range(int(length / CFG.slow_speed / 0.05) + 1):
        t = k * 0.05
        x, y = robot.x + ux * CFG.slow_speed * t, robot.y + uy * CFG.slow_speed * t
        dx, dy = walker.x + walker.vx * t - x, walker.y + walker.vy * t - y
        towards = dx * ux + dy * uy > 0.0  # the robot's own motion is towards them ...
        shrinking = dx * (walker.vx - ux * CFG.slow_speed) + dy * (walker.vy - uy * CFG.slow_speed)
        if towards and shrinking < 0.0:  # ... and the gap shrinks
            closest = min(closest, math.hypot(dx, dy))
    return closest


@pytest.mark.parametrize("offset", [0.3, 0.4, -0.4])
def test_no_spot_across_the_way_of_a_walker_coming_on(offset: float) -> None:
    robot = Pose2D(3.0, 1.5, 0.0)
    # 1.5 m ahead, walking down the corridor just beside the robot: their line passes
    # ``offset`` to its side. The old spots crossed in front of them to the far side.
    walker = Person(4.5, 1.5 + offset, -0.8, 0.0)
    spots = aside_spots(_Corridor(), robot, PeopleView((walker,)), CFG, limit=50)
    assert spots, "a 3 m corridor has room on the robot's side of their line"
    robot_side = _side(walker, robot.x, robot.y)
    for spot in spots:
        assert _side(walker, spot.x, spot.y) * robot_side > 0.0, spot  # not across their way
        assert abs(_side(walker, spot.x, spot.y)) >= CFG.social_distance - 1e-9
        assert _closes_in_on(walker, robot, spot) >= CFG.social_distance, spot


def test_the_side_the_walker_is_not_heading_to_comes_first() -> None:
    robot = Pose2D(3.0, 1.5, 0.0)
    # In an open room, 2 m ahead, heading to pass the robot on its left (+y).
    walker = Person(5.0, 1.5, -0.8, 0.3)
    spots = aside_spots(FakeCostmap(), robot, PeopleView((walker,)), CFG)  # type: ignore[arg-type]
    assert spots and spots[0].y < robot.y  # to the right, away from where they head


def test_no_spot_on_the_line_behind_a_walker_walking_away() -> None:
    """People turn back: a walker shuttling between two doors came back 2 s after a robot
    stepped onto their line behind them, into the doorway they had just left (bench fleet
    seed 3). The spots behind them on their line were the ones farthest from their way ahead."""
    robot = Pose2D(3.0, 1.0, math.pi / 2)
    walker = Person(3.0, 2.0, 0.0, 0.7)  # 1 m ahead of it, walking away along its heading
    spots = aside_spots(FakeCostmap(), robot, PeopleView((walker,)), CFG, limit=50)  # type: ignore[arg-type]
    assert spots
    for spot in spots:
        behind = walker.y - spot.y  # how far back along their line
        if 0.0 < behind <= 1.5:
            assert abs(spot.x - walker.x) >= CFG.social_distance - 1e-9, spot


def _wait(*people: Person) -> PeopleWait:
    wait = PeopleWait(CFG, FakeCostmap(), ScriptedPlanner(), ScriptedController(),  # type: ignore[arg-type]
                      robot_radius=0.25)
    wait.people = PeopleView(people)
    return wait


def test_stepping_aside_drives_at_no_one_in_their_space_but_keeps_turning() -> None:
    wait = _wait(Person(0.6, 0.3, -0.5, 0.0))  # ahead, a little to the left, coming on
    twist = wait._aside_polite(Pose2D(), Twist(0.3, -0.6))
    towards = 0.6 / math.hypot(0.6, 0.3)
    assert twist.linear * towards <= 0.005 + 1e-9  # its own closing speed: next to nothing
    assert twist.angular == -0.6  # still turning off their way, not standing
    # Facing away from them it drives on, at the slow speed.
    away = wait._aside_polite(Pose2D(0.0, 0.0, -math.pi / 2), Twist(0.5, 0.0))
    assert away.linear == pytest.approx(CFG.slow_speed)
    # Someone beyond their space (and the margin) does not hold it.
    far = _wait(Person(1.2, 0.0))._aside_polite(Pose2D(), Twist(0.3, 0.0))
    assert far.linear == pytest.approx(0.3)


def test_someone_coming_on_is_met_early_enough_to_brake() -> None:
    # 1.1 m ahead, walking at the robot at 0.8 m/s: in 0.5 s they are at 0.7 m, inside their
    # space; a robot still driving at them then would close in while it brakes.
    coming = _wait(Person(1.1, 0.0, -0.8, 0.0)).slow(Pose2D(), Twist(0.6, 0.0))
    standing = _wait(Person(1.1, 0.0)).slow(Pose2D(), Twist(0.6, 0.0))
    assert coming.linear == 0.0
    assert standing.linear == pytest.approx((1.1 - CFG.social_distance) / CFG.approach_time)
    # Walking away, they are judged where they are (the robot follows at their pace).
    leaving = _wait(Person(0.8, 0.0, 0.4, 0.0)).slow(Pose2D(), Twist(0.6, 0.0))
    assert leaving.linear == pytest.approx(0.4)


def test_a_way_aside_held_by_someone_is_chosen_again_once_then_backed_off() -> None:
    controller = ScriptedController()  # drives straight ahead at 0.5 m/s, whatever the spot
    wait = PeopleWait(CFG, FakeCostmap(), ScriptedPlanner(), controller,  # type: ignore[arg-type]
                      robot_radius=0.25)
    wait.people = PeopleView((Person(0.6, 0.0),))  # face to face, inside their space
    pose = Pose2D()
    path = Path(np.array([[0.0, 0.0], [5.0, 0.0]]))
    wait.begin(pose, 0.0)
    twists = []
    for k in range(int(3 * CFG.hold_before_wait / 0.1)):
        step = wait.tick(pose, Twist(), CFG.give_way_after + k * 0.1, 0.1, path, lambda _: path)
        twists.append(step.twist)
    assert all(t.linear <= 0.005 + 1e-9 for t in twists)  # never at them
    assert controller.paths == 2  # the way aside once, and another for where they are now
    assert twists[-1].linear < 0.0  # then backing off: no standing face to face


class _RoundTheWall:
    """Plans every way as a detour of 4 m out and back: each spot near the robot lies behind a
    wall, reached through the next door along (as from floor 2's corridor crossing into a
    room beside it)."""

    calls = 0

    def plan(self, costmap: object, start: Pose2D, goal: Pose2D, *,
             goal_tolerance: float | None = None) -> Path:
        self.calls += 1
        return Path(np.array([[start.x, start.y], [start.x - 4.0, start.y],
                              [goal.x - 4.0, goal.y], [goal.x, goal.y]]))


def test_a_spot_reached_only_round_a_wall_is_no_step_aside_the_robot_backs_up() -> None:
    planner = _RoundTheWall()
    controller = ScriptedController()
    wait = PeopleWait(CFG, FakeCostmap(), planner, controller,  # type: ignore[arg-type]
                      robot_radius=0.25)
    wait.people = PeopleView((Person(0.9, 0.0),))  # face to face, waiting for the robot
    pose = Pose2D()
    path = Path(np.array([[0.0, 0.0], [5.0, 0.0]]))
    wait.begin(pose, 0.0)
    step = wait.tick(pose, Twist(), CFG.give_way_after, 0.1, path, lambda _: path)
    assert planner.calls >= 1  # spots were found and tried ...
    assert controller.paths == 0  # ... but none is a step aside: no way aside is followed
    assert step.twist.linear < 0.0  # it backs up off their way instead


def test_a_step_aside_stays_near_where_the_wait_began() -> None:
    """Stepped aside once already (2 m from where it began to wait) and face to face again, the
    robot takes no spot farther on: step after step away from one walker is a retreat (on floor
    2 of the demo, down a room's side passage ahead of the walker heading there, into the
    room, and back up it head-on into a robot: issue 36)."""
    controller = ScriptedController()
    wait = PeopleWait(CFG, FakeCostmap(), ScriptedPlanner(), controller,  # type: ignore[arg-type]
                      robot_radius=0.25)
    start = Pose2D()
    path = Path(np.array([[0.0, 0.0], [5.0, 0.0]]))
    wait.people = PeopleView((Person(0.9, 0.0),))
    wait.begin(start, 0.0)
    here = Pose2D(2.0, 0.0)
    wait.people = PeopleView((Person(2.9, 0.0),))  # face to face again, waiting for it
    wait.tick(here, Twist(), CFG.give_way_after, 0.1, path, lambda _: path)
    spot = wait._aside
    assert spot is None or spot.distance_to(start) <= 2.0 + 1e-9, spot
    # Without the bound the same tick steps aside beyond it (the test can fail).
    free = PeopleWait(CFG, FakeCostmap(), ScriptedPlanner(), ScriptedController(),  # type: ignore[arg-type]
                      robot_radius=0.25)
    free.people = wait.people
    free.begin(here, 0.0)
    free.tick(here, Twist(), CFG.give_way_after, 0.1, path, lambda _: path)
    assert free._aside is not None and free._aside.distance_to(start) > 2.0
