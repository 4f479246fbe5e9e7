"""The navigator's state machine with scripted planner and controller doubles.

The doubles let each test force one situation (no path, blocked, stuck, lost, e-stop) and check
the exact sequence of events and the final state, on a hand-advanced clock.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pytest

from polynav.control.interface import ControlCommand, ControlStatus
from polynav.control.progress_checker import ProgressChecker, ProgressCheckerConfig
from polynav.errors import ConfigError
from polynav.geometry import Pose2D, Twist
from polynav.localization.interface import LocalizationEstimate, LocalizationState
from polynav.maps import costs
from polynav.maps.costmap import CostmapConfig, CostSnapshot
from polynav.maps.map import MapInfo
from polynav.nav import events
from polynav.nav.attempt import FailureReason, GoalOptions, NavigationState
from polynav.nav.navigator import Navigator
from polynav.nav.navigator_config import NavigatorConfig
from polynav.nav.people import PeopleConfig, PeopleView, Person
from polynav.planning.errors import GoalOccupied, NoPath, OutsideMap, PlanningError
from polynav.planning.path import Path

DT = 0.05


@dataclass
class FakeCostmap:
    """An open 40 m grid, counting the clearings asked of it."""

    cleared: int = 0
    cleared_around: int = 0
    lethal_behind: bool = False
    goal_in_wall: bool = False
    info: MapInfo = MapInfo(0.05, 800, 800, Pose2D(-20.0, -20.0, 0.0))
    costs: np.ndarray = field(default_factory=lambda: np.zeros((800, 800), dtype=np.uint8))
    config: CostmapConfig = field(default_factory=CostmapConfig)  # unknown taken as free

    def clear_obstacles(self) -> None:
        self.cleared += 1

    def clear_obstacles_around(self, x: float, y: float, radius: float) -> None:
        self.cleared_around += 1

    def cost_at(self, x: float, y: float) -> int:
        return costs.LETHAL if self.lethal_behind else costs.FREE

    def map_cost_at(self, x: float, y: float) -> int:
        return costs.LETHAL if self.goal_in_wall else costs.FREE

    def map_costs(self) -> CostSnapshot:
        return CostSnapshot(self.info, self.costs)

    def planning_costs(self) -> FakeCostmap:
        return self

    shut_doors: tuple[()] = ()


@dataclass
class ScriptedPlanner:
    """Raises the scripted errors in order, then plans straight lines."""

    failures: list[PlanningError] = field(default_factory=list)
    calls: int = 0
    goals: list[Pose2D] = field(default_factory=list)

    def plan(
        self, costmap: object, start: Pose2D, goal: Pose2D, *, goal_tolerance: float | None = None
    ) -> Path:
        self.calls += 1
        self.goals.append(goal)
        if self.failures:
            raise self.failures.pop(0)
        return Path(np.array([[start.x, start.y], [goal.x, goal.y]]))


@dataclass
class ScriptedController:
    """Returns the scripted statuses in order, then the last one for ever."""

    statuses: list[ControlStatus] = field(default_factory=lambda: [ControlStatus.TRACKING])
    paths: int = 0

    def set_path(self, path: Path, goal: Pose2D) -> None:
        self.paths += 1

    def compute(self, pose: Pose2D, velocity: Twist, costmap: object, dt: float) -> ControlCommand:
        status = self.statuses.pop(0) if len(self.statuses) > 1 else self.statuses[0]
        moving = status in (ControlStatus.TRACKING, ControlStatus.SLOWING)
        return ControlCommand(Twist(0.5 if moving else 0.0, 0.0), status)

    def set_goal_options(self, *, yaw_tolerance: float | None, reverse_allowed: bool) -> None:
        self.goal_options = (yaw_tolerance, reverse_allowed)

    def reset(self) -> None:
        pass


def _estimate(pose: Pose2D, state: LocalizationState = LocalizationState.TRACKING) -> (
    LocalizationEstimate
):
    return LocalizationEstimate(stamp=0.0, pose=pose, quality=1.0, state=state)


class Harness:
    def __init__(self, planner: ScriptedPlanner, controller: ScriptedController,
                 config: NavigatorConfig | None = None,
                 people: PeopleConfig | None = None) -> None:
        self.costmap = FakeCostmap()
        self.log: list[events.NavigationEvent] = []
        self.nav = Navigator(
            self.costmap,  # type: ignore[arg-type]
            planner,
            controller,
            ProgressChecker(ProgressCheckerConfig(required_movement_radius=0.5,
                                                  movement_time_allowance=2.0)),
            config=config,
            people=people,
            on_event=self.log.append,
        )
        self.now = 0.0
        self.pose = Pose2D()
        self.estop = False
        self.localization = LocalizationState.TRACKING
        self.people = PeopleView()
        self.twists: list[Twist] = []

    def run(self, seconds: float, *, move: bool = False) -> None:
        for _ in range(round(seconds / DT)):
            twist = self.nav.tick(self.now, _estimate(self.pose, self.localization), Twist(),
                                  self.estop, people=self.people)
            self.twists.append(twist)
            if move:
                self.pose = Pose2D(self.pose.x + twist.linear * DT, self.pose.y, self.pose.theta)
            self.now += DT

    def kinds(self) -> list[str]:
        return [type(e).__name__ for e in self.log]


def test_arrival_ends_succeeded_with_distance_travelled() -> None:
    h = Harness(ScriptedPlanner(), ScriptedController(
        [ControlStatus.TRACKING] * 20 + [ControlStatus.ARRIVED]))
    h.nav.start(Pose2D(5.0, 0.0, 0.0), h.now)
    h.run(2.0, move=True)
    attempt = h.nav.attempt
    assert attempt is not None and attempt.state is NavigationState.SUCCEEDED
    assert attempt.distance_travelled == pytest.approx(20 * 0.5 * DT)
    assert h.kinds() == ["NavigationStarted", "PathPlanned", "NavigationSucceeded"]
    assert h.twists[-1] == Twist()


def test_no_path_clears_the_costmap_once_then_fails() -> None:
    # The third plan is on the map alone: walled in there too, so the failure is final.
    planner = ScriptedPlanner([NoPath("walled in")] * 3)
    h = Harness(planner, ScriptedController())
    h.nav.start(Pose2D(5.0, 0.0, 0.0), h.now)
    h.run(0.5)
    attempt = h.nav.attempt
    assert attempt is not None and attempt.state is NavigationState.FAILED
    assert attempt.reason is FailureReason.NO_PATH
    assert h.costmap.cleared == 1 and planner.calls == 3
    assert h.kinds() == [
        "NavigationStarted", "PlanFailed", "NavigationRetry", "PlanFailed", "NavigationFailed"
    ]
    assert attempt.ended_at == pytest.approx(DT)


def test_no_path_that_clearing_resolves_goes_on() -> None:
    h = Harness(ScriptedPlanner([NoPath("a person")]), ScriptedController())
    h.nav.start(Pose2D(5.0, 0.0, 0.0), h.now)
    h.run(0.5, move=True)
    assert h.nav.state is NavigationState.RUNNING
    assert h.kinds()[:4] == ["NavigationStarted", "PlanFailed", "NavigationRetry", "PathPlanned"]


def test_goal_occupied_and_outside_map_reasons() -> None:
    h = Harness(ScriptedPlanner([GoalOccupied("wall"), GoalOccupied("wall")]),
                ScriptedController())
    h.costmap.goal_in_wall = True
    h.nav.start(Pose2D(5.0, 0.0, 0.0), h.now)
    h.run(0.5)
    assert h.nav.attempt is not None and h.nav.attempt.reason is FailureReason.GOAL_OCCUPIED
    h2 = Harness(ScriptedPlanner([OutsideMap("far")]), ScriptedController())
    h2.nav.start(Pose2D(500.0, 0.0, 0.0), h2.now)
    h2.run(0.2)
    assert h2.nav.attempt is not None and h2.nav.attempt.reason is FailureReason.NO_PATH


def test_a_way_the_map_has_but_something_closes_is_retried_and_taken_once_open() -> None:
    # Closed twice on the live costmap (cleared between), open on the map alone: a robot at
    # the corridor's mouth, say. Retried, not failed; the way opens on the next plan.
    planner = ScriptedPlanner([NoPath("closed"), NoPath("closed")])
    h = Harness(planner, ScriptedController(
        [ControlStatus.TRACKING] * 200 + [ControlStatus.ARRIVED]))
    h.nav.start(Pose2D(5.0, 0.0, 0.0), h.now)
    h.run(20.0, move=True)
    attempt = h.nav.attempt
    assert attempt is not None and attempt.state is NavigationState.SUCCEEDED
    assert "NavigationFailed" not in h.kinds()
    retries = [e for e in h.log if isinstance(e, events.NavigationRetry)]
    assert [e.cause for e in retries] == ["no path", "no way past what stands in it"]


def test_a_way_closed_by_something_that_stays_ends_stuck_after_the_retry_budget() -> None:
    planner = ClosedOnLiveCostmap()
    h = Harness(planner, ScriptedController())
    h.nav.start(Pose2D(5.0, 0.0, 0.0), h.now)
    h.run(60.0, move=True)
    attempt = h.nav.attempt
    assert attempt is not None and attempt.state is NavigationState.FAILED
    assert attempt.reason is FailureReason.STUCK
    assert "no way past what stands in it" in attempt.message
    assert attempt.ended_at is not None and attempt.ended_at >= h.nav.config.retry_min_time


def test_a_caller_with_its_own_retry_limit_hears_no_path_at_once() -> None:
    planner = ClosedOnLiveCostmap()
    h = Harness(planner, ScriptedController())
    h.nav.start(Pose2D(5.0, 0.0, 0.0), h.now, GoalOptions(max_retries=1))
    h.run(1.0)
    attempt = h.nav.attempt
    assert attempt is not None and attempt.reason is FailureReason.NO_PATH
    assert planner.on_map == 0


@dataclass
class ClosedOnLiveCostmap:
    """No way on the live costmap, a straight one on the map alone (another robot in it)."""

    calls: int = 0
    on_map: int = 0

    def plan(self, costmap: object, start: Pose2D, goal: Pose2D, *,
             goal_tolerance: float | None = None) -> Path:
        self.calls += 1
        if isinstance(costmap, FakeCostmap):
            raise NoPath("a robot in the way")
        self.on_map += 1
        return Path(np.array([[start.x, start.y], [goal.x, goal.y]]))


def test_goal_held_by_something_off_the_map_is_waited_for_then_reached() -> None:
    # Cleared and still occupied, but free on the map: a robot standing there, which leaves.
    h = Harness(ScriptedPlanner([GoalOccupied("robot")] * 6), ScriptedController(),
                NavigatorConfig(goal_wait=60.0, goal_wait_period=1.0))
    h.nav.start(Pose2D(5.0, 0.0, 0.0), h.now)
    h.run(3.0)
    assert h.nav.state is NavigationState.RUNNING
    waits = [e for e in h.log if isinstance(e, events.NavigationWaiting)]
    assert [w.cause for w in waits] == ["goal occupied"]
    assert all(t == Twist() for t in h.twists[-20:])  # it stands while it waits
    h.run(5.0, move=True)
    assert "PathPlanned" in h.kinds()
    assert h.kinds().count("NavigationWaiting") == 1  # told once, not at every try
    assert h.nav.state in (NavigationState.RUNNING, NavigationState.SUCCEEDED)


def test_goal_that_stays_occupied_fails_goal_occupied_after_the_patience() -> None:
    planner = ScriptedPlanner([GoalOccupied("robot")] * 1000)
    h = Harness(planner, ScriptedController(), NavigatorConfig(goal_wait=30.0))
    h.nav.start(Pose2D(5.0, 0.0, 0.0), h.now)
    h.run(29.0)
    assert h.nav.state is NavigationState.RUNNING
    h.run(2.0)
    attempt = h.nav.attempt
    assert attempt is not None and attempt.reason is FailureReason.GOAL_OCCUPIED
    assert "30 s" in attempt.message
    assert 28 <= planner.calls <= 34  # one try a second, not one a control period


def test_goal_wait_off_fails_a_held_goal_at_once() -> None:
    h = Harness(ScriptedPlanner([GoalOccupied("robot")] * 2), ScriptedController(),
                NavigatorConfig(goal_wait=0.0))
    h.nav.start(Pose2D(5.0, 0.0, 0.0), h.now)
    h.run(0.5)
    assert h.nav.state is NavigationState.FAILED
    assert "NavigationWaiting" not in h.kinds()


def test_a_goal_s_own_goal_wait_overrides_the_navigator_s() -> None:
    # A lift's entry leg: the sequence has its own retries, so an occupied spot fails at once.
    h = Harness(ScriptedPlanner([GoalOccupied("robot")] * 2), ScriptedController(),
                NavigatorConfig(goal_wait=120.0))
    h.nav.start(Pose2D(5.0, 0.0, 0.0), h.now, GoalOptions(goal_wait=0.0))
    h.run(0.5)
    assert h.nav.state is NavigationState.FAILED
    h2 = Harness(ScriptedPlanner([GoalOccupied("robot")] * 1000), ScriptedController(),
                 NavigatorConfig(goal_wait=0.0))
    h2.nav.start(Pose2D(5.0, 0.0, 0.0), h2.now, GoalOptions(goal_wait=10.0))
    h2.run(9.0)
    assert h2.nav.state is NavigationState.RUNNING
    h2.run(2.0)
    assert h2.nav.state is NavigationState.FAILED
    with pytest.raises(ValueError, match="goal_wait"):
        GoalOptions(goal_wait=-1.0)


def test_stuck_robot_climbs_the_recovery_ladder_then_fails_stuck_after_the_min_time() -> None:
    config = NavigatorConfig(max_retries=3, retry_min_time=30.0)
    h = Harness(ScriptedPlanner(), ScriptedController(), config)
    h.nav.start(Pose2D(5.0, 0.0, 0.0), h.now)
    h.run(90.0, move=False)  # the wheels spin, the robot goes nowhere
    attempt = h.nav.attempt
    assert attempt is not None and attempt.state is NavigationState.FAILED
    assert attempt.reason is FailureReason.STUCK
    retries = [e for e in h.log if isinstance(e, events.NavigationRetry)]
    full = "clear around, back up, rotate, wait"
    assert [r.recovery for r in retries] == [
        "clear around", "clear around, back up", "clear around, back up, rotate",
    ] + [full] * (len(retries) - 3)
    # More than 3 failures at this place, but it is given up only 30 s after the first.
    assert attempt.retries == len(retries) + 1 > 4
    assert attempt.ended_at is not None and attempt.ended_at - retries[0].stamp >= 30.0
    assert attempt.ended_at - retries[-1].stamp < 30.0
    assert h.costmap.cleared_around == len(retries)


def test_failures_at_a_place_left_behind_are_forgotten() -> None:
    # Blocked four times in a row, each time after driving on 1.5 m: never stuck.
    statuses = ([ControlStatus.TRACKING] * 60 + [ControlStatus.BLOCKED]) * 4
    controller = ScriptedController(statuses + [ControlStatus.TRACKING])
    h = Harness(ScriptedPlanner(), controller,
                NavigatorConfig(max_retries=1, blocked_wait=0.1, retry_min_time=0.0))
    h.nav.start(Pose2D(50.0, 0.0, 0.0), h.now)
    h.run(20.0, move=True)
    assert h.nav.state is NavigationState.RUNNING
    retries = [e for e in h.log if isinstance(e, events.NavigationRetry)]
    assert [r.recovery for r in retries] == ["clear around"] * 4


def test_quick_blocks_at_one_place_are_not_stuck_before_the_min_time() -> None:
    # Issue 18: four blocks within 0.75 m in 6 s ended the goal. Now they climb the ladder.
    controller = ScriptedController([ControlStatus.BLOCKED] * 400 + [ControlStatus.TRACKING])
    h = Harness(ScriptedPlanner(), controller,
                NavigatorConfig(max_retries=3, blocked_wait=0.1, retry_min_time=30.0))
    h.nav.start(Pose2D(5.0, 0.0, 0.0), h.now)
    h.run(25.0)
    assert h.nav.state is NavigationState.RUNNING
    assert len([e for e in h.log if isinstance(e, events.NavigationRetry)]) >= 4


def test_blocked_waits_then_replans() -> None:
    controller = ScriptedController([ControlStatus.BLOCKED] + [ControlStatus.TRACKING])
    planner = ScriptedPlanner()
    config = NavigatorConfig(blocked_wait=1.0)
    h = Harness(planner, controller, config)
    h.nav.start(Pose2D(5.0, 0.0, 0.0), h.now)
    h.run(0.9)
    assert planner.calls == 1
    assert all(t == Twist() for t in h.twists)
    h.run(0.3, move=True)
    assert planner.calls == 2
    assert h.kinds()[:5] == ["NavigationStarted", "PathPlanned", "NavigationBlocked",
                             "NavigationRetry", "PathPlanned"]
    assert h.twists[-1].linear > 0


def test_a_route_closed_after_it_was_planned_is_replanned_at_once_and_only_once() -> None:
    planner = ScriptedPlanner()
    h = Harness(planner, ScriptedController(), NavigatorConfig(replan_period=3.0,
                                                               closed_route_replan_period=0.5))
    h.nav.start(Pose2D(10.0, 0.0, 0.0), h.now)
    h.run(1.0, move=True)
    assert planner.calls == 1
    ix, iy = h.costmap.info.world_to_cell(6.0, 0.0)
    h.costmap.costs[iy, ix] = costs.LETHAL  # the lidar marks a post on the route ahead
    h.run(0.1, move=True)
    assert planner.calls == 2
    # The double plans through the post again: a route planned closed waits for the period,
    # 3 s after the re-plan at 1.05 s.
    h.run(2.8, move=True)
    assert planner.calls == 2
    h.run(0.2, move=True)
    assert planner.calls == 3


def test_estop_holds_without_failing_and_releases_with_a_new_plan() -> None:
    planner = ScriptedPlanner()
    h = Harness(planner, ScriptedController())
    h.nav.start(Pose2D(50.0, 0.0, 0.0), h.now)
    h.run(0.5, move=True)
    h.estop = True
    h.run(30.0, move=True)
    assert h.nav.state is NavigationState.RUNNING
    assert all(t == Twist() for t in h.twists[-600:])
    h.estop = False
    h.run(0.2, move=True)
    assert "NavigationHeld" in h.kinds() and "NavigationReleased" in h.kinds()
    assert h.twists[-1].linear > 0


def test_estop_can_be_configured_to_fail() -> None:
    h = Harness(ScriptedPlanner(), ScriptedController(), NavigatorConfig(estop_fail_after=2.0))
    h.nav.start(Pose2D(50.0, 0.0, 0.0), h.now)
    h.estop = True
    h.run(3.0)
    assert h.nav.attempt is not None and h.nav.attempt.reason is FailureReason.ESTOP


def test_lost_localization_fails_after_the_grace_period_only() -> None:
    h = Harness(ScriptedPlanner(), ScriptedController(), NavigatorConfig(localization_grace=2.0))
    h.nav.start(Pose2D(50.0, 0.0, 0.0), h.now)
    h.localization = LocalizationState.LOST
    h.run(1.9)
    assert h.nav.state is NavigationState.RUNNING
    h.run(0.2)
    assert h.nav.attempt is not None
    assert h.nav.attempt.reason is FailureReason.LOCALIZATION_LOST


def test_pause_resume_cancel() -> None:
    h = Harness(ScriptedPlanner(), ScriptedController())
    assert not h.nav.pause(h.now) and not h.nav.resume(h.now) and not h.nav.cancel(h.now)
    h.nav.start(Pose2D(50.0, 0.0, 0.0), h.now)
    h.run(0.5, move=True)
    assert h.nav.pause(h.now)
    h.run(1.0, move=True)
    assert all(t == Twist() for t in h.twists[-20:])
    assert h.nav.resume(h.now)
    h.run(0.2, move=True)
    assert h.twists[-1].linear > 0
    assert h.nav.cancel(h.now)
    h.run(0.2)
    assert h.nav.state is NavigationState.CANCELED
    assert h.kinds()[-1] == "NavigationCanceled"


def test_new_goal_cancels_the_running_one() -> None:
    h = Harness(ScriptedPlanner(), ScriptedController())
    first = h.nav.start(Pose2D(50.0, 0.0, 0.0), h.now)
    second = h.nav.start(Pose2D(-5.0, 0.0, 0.0), h.now)
    assert second == first + 1
    assert h.kinds() == ["NavigationStarted", "NavigationCanceled", "NavigationStarted"]


def test_config_rejects_bad_values() -> None:
    with pytest.raises(ConfigError):
        NavigatorConfig(max_retries=-1)
    with pytest.raises(ConfigError):
        NavigatorConfig(blocked_wait=0.0)


# -- people ----------------------------------------------------------------------------------


def test_slows_to_the_slow_speed_within_the_social_distance_only() -> None:
    h = Harness(ScriptedPlanner(), ScriptedController())
    h.nav.start(Pose2D(5.0, 0.0, 0.0), h.now)
    h.run(0.2)
    assert h.twists[-1].linear == pytest.approx(0.5)
    h.people = PeopleView((Person(0.0, 0.6),))  # beside the robot, inside 0.8 m
    h.run(0.2)
    assert h.twists[-1].linear == pytest.approx(PeopleConfig().slow_speed)
    h.people = PeopleView((Person(0.0, 2.0),))
    h.run(0.2)
    assert h.twists[-1].linear == pytest.approx(0.5)


def test_blocked_by_a_person_on_the_path_waits_then_goes_when_they_leave() -> None:
    controller = ScriptedController([ControlStatus.BLOCKED, ControlStatus.TRACKING])
    planner = ScriptedPlanner()
    h = Harness(planner, controller, NavigatorConfig(blocked_wait=0.1, max_retries=0))
    h.nav.start(Pose2D(5.0, 0.0, 0.0), h.now)
    h.people = PeopleView((Person(2.0, 0.1),))  # standing on the way, 2 m ahead
    h.run(DT)  # planned, then blocked by them
    planner.failures = [NoPath("person")] * 10  # no way past them while they stand there
    h.run(10.0)
    assert h.nav.state is NavigationState.RUNNING  # no retry counted: max_retries 0 holds
    assert h.kinds()[:4] == ["NavigationStarted", "PathPlanned", "NavigationBlocked",
                             "NavigationWaiting"]
    assert all(t == Twist() for t in h.twists[3:])
    h.people = PeopleView((Person(2.0, 3.0),))  # walked off the way
    planner.failures = []
    h.run(1.0, move=True)
    assert h.kinds().count("NavigationWaiting") == 1
    assert h.kinds()[-1] == "PathPlanned" and h.twists[-1].linear > 0.0


def _held_by_a_person() -> tuple[Harness, ScriptedController]:
    """A goal 5 m ahead with someone standing 1 m in front (patience 5 s); the controller
    reports BLOCKED until told otherwise."""
    controller = ScriptedController([ControlStatus.BLOCKED])
    h = Harness(ScriptedPlanner(), controller, NavigatorConfig(blocked_wait=0.1),
                PeopleConfig(patience=5.0))
    h.nav.start(Pose2D(5.0, 0.0, 0.0), h.now)
    h.people = PeopleView((Person(1.0, 0.0),))
    return h, controller


def _assert_failed_blocked_by_person(h: Harness, *, after: float,
                                     within: tuple[float, float]) -> None:
    """The goal failed ``blocked by person`` between ``within`` seconds after ``after``."""
    attempt = h.nav.attempt
    assert attempt is not None and attempt.state is NavigationState.FAILED
    assert attempt.reason is FailureReason.BLOCKED_BY_PERSON
    assert attempt.ended_at is not None
    assert within[0] < attempt.ended_at - after < within[1]


def test_people_who_never_make_way_fail_the_goal_after_the_patience() -> None:
    h, controller = _held_by_a_person()
    h.run(4.9)
    assert h.nav.state is NavigationState.RUNNING
    h.run(0.5)
    attempt = h.nav.attempt
    assert attempt is not None and attempt.state is NavigationState.FAILED
    assert attempt.reason is FailureReason.BLOCKED_BY_PERSON
    waiting = next(e for e in h.log if isinstance(e, events.NavigationWaiting))
    assert attempt.ended_at - waiting.stamp == pytest.approx(5.0, abs=DT + 1e-9)


def test_time_paused_is_not_spent_waiting_for_people() -> None:
    # A walker makes way after 2 s; the goal is paused 30 s (the fleet: in line for a
    # corridor) before the robot has moved on; resumed, the next walker blocks it at once. The
    # wait goes on with the 3 s of patience it had left, not failed with no wait at all.
    h, controller = _held_by_a_person()
    h.run(2.0)
    assert h.kinds()[-1] == "NavigationWaiting"
    h.people = PeopleView()
    controller.statuses = [ControlStatus.TRACKING]
    h.run(0.5)  # the way is open: planned, following
    assert h.kinds()[-1] == "PathPlanned"
    assert h.nav.pause(h.now)
    h.run(30.0)
    assert h.nav.resume(h.now)
    resumed = h.now
    h.people = PeopleView((Person(1.0, 0.0),))
    controller.statuses = [ControlStatus.BLOCKED]
    h.run(2.0)
    assert h.nav.state is NavigationState.RUNNING
    h.run(2.0)
    _assert_failed_blocked_by_person(h, after=resumed, within=(2.0, 4.0))


def test_no_path_with_a_person_at_the_robot_waits_instead_of_failing() -> None:
    planner = ScriptedPlanner([NoPath("door"), NoPath("door"), NoPath("door")])
    h = Harness(planner, ScriptedController())
    h.people = PeopleView((Person(0.8, 0.0),))
    h.nav.start(Pose2D(5.0, 0.0, 0.0), h.now)
    h.run(3.0)
    assert h.nav.state is NavigationState.RUNNING
    assert "NavigationWaiting" in h.kinds() and h.costmap.cleared == 0
    h.people = PeopleView()
    h.run(0.5, move=True)
    assert h.kinds()[-1] == "PathPlanned"


def test_a_no_path_after_a_way_was_found_past_people_is_cleared_again_before_it_is_final(
) -> None:
    # Cleared once, then a way found while waiting for someone: a later "no path" (marks a
    # walker left in a door) is cleared once more, not final at once.
    planner = ScriptedPlanner([NoPath("door")])
    controller = ScriptedController([ControlStatus.TRACKING])
    h = Harness(planner, controller, NavigatorConfig(blocked_wait=0.1))
    h.nav.start(Pose2D(5.0, 0.0, 0.0), h.now)
    h.run(DT)  # no path: the costmap is cleared
    assert h.costmap.cleared == 1
    planner.failures = [NoPath("door")]
    h.people = PeopleView((Person(3.0, 2.0),))  # in view, off the way
    h.run(3.0)  # still no path: wait for them, and the wait finds a way
    assert "NavigationWaiting" in h.kinds() and h.kinds()[-1] == "PathPlanned"
    h.people = PeopleView()
    controller.statuses = [ControlStatus.BLOCKED]
    planner.failures = [NoPath("marks in the door")]
    h.run(1.0)
    assert h.nav.state is NavigationState.RUNNING
    assert h.costmap.cleared == 2


def test_people_config_rejects_bad_values() -> None:
    for bad in ({"social_distance": 0.0}, {"patience": -1.0}, {"layer_cost": 253},
                {"horizon": float("nan")}, {"wait_replan_period": float("inf")}):
        with pytest.raises(ConfigError):
            PeopleConfig(**bad)  # type: ignore[arg-type]


def test_someone_face_to_face_for_a_while_is_given_way() -> None:
    controller = ScriptedController([ControlStatus.BLOCKED])
    planner = ScriptedPlanner()
    h = Harness(planner, controller, NavigatorConfig(blocked_wait=0.1))
    h.nav.start(Pose2D(5.0, 0.0, 0.0), h.now)
    h.people = PeopleView((Person(0.9, 0.0),))  # right in front, waiting for us
    h.run(DT)
    planner.failures = [NoPath("person")] * 10
    h.run(PeopleConfig().give_way_after + 0.2)
    assert all(t == Twist() for t in h.twists[:-5])
    assert h.twists[-1].linear < 0.0 and h.twists[-1].angular == 0.0  # backing off
    h.run(5.0, move=True)
    assert -0.55 <= h.pose.x <= -0.45  # once, by the give-way distance
    assert h.nav.state is NavigationState.RUNNING


def test_a_new_goal_does_not_inherit_the_last_goal_s_watch_for_people() -> None:
    # A way found past people makes every re-plan of that goal plan the whole way for a while
    # (people_detour_watch). The next goal starts without that watch: its periodic re-plans
    # plan the next stretch of its own route, as they would in a freshly started navigator.
    planner = ScriptedPlanner([NoPath("door")])
    h = Harness(planner, ScriptedController([ControlStatus.TRACKING]),
                NavigatorConfig(blocked_wait=0.1, people_detour_watch=60.0))
    h.nav.start(Pose2D(5.0, 0.0, 0.0), h.now)
    h.run(DT)
    planner.failures = [NoPath("door")]
    h.people = PeopleView((Person(3.0, 2.0),))
    h.run(3.0)  # the wait finds a way past them: the watch begins
    assert "NavigationWaiting" in h.kinds() and h.kinds()[-1] == "PathPlanned"
    h.people = PeopleView()
    goal = Pose2D(30.0, 0.0, 0.0)
    h.nav.start(goal, h.now)
    h.run(DT, move=True)
    assert planner.goals[-1] == goal  # a goal's first plan is the whole way
    first = len(planner.goals)
    h.run(NavigatorConfig().replan_period + 0.2, move=True)
    replans = planner.goals[first:]
    assert replans and all(g.x < goal.x - 1.0 for g in replans)  # the next stretch only


@pytest.mark.parametrize("make_way", [True, False])
def test_a_goal_paused_in_line_still_makes_way_for_someone_it_holds_up(make_way: bool) -> None:
    # Paused by the fleet's traffic rule (make_way), the robot stood frozen in a corridor while
    # a walker waited for it, and the robot ahead, holding the passage, waited for that walker
    # (issue 36, floor 2's room_205 door). In line, it steps aside once someone has stood face
    # to face with it for give_way_after; an operator's pause stays a standstill.
    planner = ScriptedPlanner()
    h = Harness(planner, ScriptedController([ControlStatus.TRACKING]))
    h.nav.start(Pose2D(5.0, 0.0, 0.0), h.now)
    h.run(0.5, move=True)
    assert h.nav.pause(h.now, make_way=make_way)
    h.twists.clear()
    h.people = PeopleView((Person(h.pose.x + 0.9, 0.0),))  # standing, right in front
    planner.failures = [NoPath("person")] * 10  # no spot aside reachable: it backs off
    h.run(PeopleConfig().give_way_after - 0.2, move=True)
    assert all(t == Twist() for t in h.twists)
    h.run(5.0, move=True)
    assert h.nav.state is NavigationState.PAUSED
    if make_way:
        assert any(t.linear < 0.0 for t in h.twists)  # backed off, once, then stood again
        assert h.twists[-1] == Twist()
    else:
        assert all(t == Twist() for t in h.twists)
    assert h.nav.resume(h.now)
    assert h.kinds()[-1] == "NavigationResumed"


def test_a_goal_paused_in_line_does_not_move_for_someone_walking_by_or_under_estop() -> None:
    h = Harness(ScriptedPlanner(), ScriptedController([ControlStatus.TRACKING]))
    h.nav.start(Pose2D(5.0, 0.0, 0.0), h.now)
    assert h.nav.pause(h.now, make_way=True)
    h.people = PeopleView((Person(0.9, 0.0, 0.0, 0.8),))  # beside it, walking past
    h.run(PeopleConfig().give_way_after + 2.0, move=True)
    h.people = PeopleView((Person(0.9, 0.0),))  # standing, but the e-stop is pressed
    h.estop = True
    h.run(PeopleConfig().give_way_after + 2.0, move=True)
    assert all(t == Twist() for t in h.twists)


def test_driving_on_between_waits_is_not_spent_waiting_for_people() -> None:
    # A walker shuttling through a door: the robot waits 3 s, drives 1.5 s after them (0.75 m,
    # short of a new episode), and meets them again. Its patience (5 s) has the 2 s it had
    # left, not 0.5 s: driving on is not waiting (issue 36, bench fleet seed 2's room_205).
    h, controller = _held_by_a_person()
    h.run(3.0)
    assert "NavigationWaiting" in h.kinds()
    h.people = PeopleView()
    controller.statuses = [ControlStatus.TRACKING]
    velocity = Twist()
    for _ in range(round(1.5 / DT)):
        twist = h.nav.tick(h.now, _estimate(h.pose), velocity, False, people=h.people)
        h.pose = Pose2D(h.pose.x + twist.linear * DT, h.pose.y, h.pose.theta)
        velocity = twist
        h.now += DT
    assert 0.5 < h.pose.x < 1.0
    h.people = PeopleView((Person(h.pose.x + 1.0, 0.0),))
    controller.statuses = [ControlStatus.BLOCKED]
    blocked = h.now
    h.run(1.5)
    assert h.nav.state is NavigationState.RUNNING
    h.run(1.0)
    _assert_failed_blocked_by_person(h, after=blocked, within=(1.5, 2.5))
