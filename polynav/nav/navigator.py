"""The navigator: one goal at a time, from plan to arrival, with retries, recoveries and events.

The navigator is a service (DESIGN §1): it owns no thread and reads no clock. The runtime calls
:meth:`Navigator.tick` once per control period with the time, the localization estimate, the
measured velocity and the e-stop state, and commands the returned velocity to the base.

Inside a running attempt the navigator moves between phases:

- *plan*: plan from the estimated pose to the goal on the live costmap;
- *follow*: the controller tracks the path; the path is re-planned every ``replan_period`` so
  new obstacles are routed around before the controller has to stop for them. The new route
  replaces the current one only if the current one is blocked or the new one is clearly shorter
  (``replan_hysteresis``): two near-equal ways round a post must not take turns;
- *blocked*: the controller stopped in front of an obstacle; wait ``blocked_wait`` (a person
  usually walks on), then recover and re-plan;
- *recover*: a rung of the recovery ladder runs before the next plan
  (:mod:`~polynav.nav.recoveries`): clear the marks around the robot, back up, rotate, wait,
  one more step for each failure at the same place;
- *goal wait*: the goal is occupied by something not on the map (another robot, a trolley):
  the robot stands, says so once, and goes on when it clears, failing after ``goal_wait``
  (:mod:`~polynav.nav.goal_wait`);
- *wait*: only people block the way (a person in a door, a group in a corridor): the robot
  stands, says so once (:class:`~polynav.nav.events.NavigationWaiting`), goes on as soon as the
  way opens or another way exists, and fails with ``blocked by person`` after the patience.
  Near people it also slows down (:mod:`~polynav.nav.people`).

An attempt's :class:`~polynav.nav.attempt.GoalOptions` add phases around that (the attempt's
``phase``): leaving a charger and docking onto one (:mod:`~polynav.nav.charger_phases`).

Each failure counts as a retry, by place and time (:mod:`~polynav.nav.retry_budget`): more than
``max_retries`` failures at one place over at least ``retry_min_time`` end the attempt with a
:class:`FailureReason`. An e-stop or lost localization holds the
robot without ending the attempt; it resumes with a fresh plan when the hold is released.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Sequence
from dataclasses import replace

import numpy as np

from polynav.control.interface import Controller, ControlStatus
from polynav.control.progress_checker import ProgressChecker
from polynav.control.tracked_path import TrackedPath
from polynav.docking.shape import front_reach
from polynav.footprint import Footprint
from polynav.geometry import Pose2D, Twist
from polynav.localization.interface import LocalizationEstimate, LocalizationState
from polynav.maps.costmap import Costmap
from polynav.nav import events, route_choice
from polynav.nav.attempt import (
    FailureReason,
    GoalOptions,
    NavigationAttempt,
    NavigationState,
    Phase,
)
from polynav.nav.back_out import BackOut, Trail
from polynav.nav.charger_phases import ChargerPhases
from polynav.nav.dock_sight import DockSight
from polynav.nav.goal_wait import GoalWait
from polynav.nav.holds import Hold
from polynav.nav.navigator_config import NavigatorConfig
from polynav.nav.passages import ClosedPassages, open_doors_on, touches_marks
from polynav.nav.people import PeopleConfig, PeopleView
from polynav.nav.people_wait import PeopleWait
from polynav.nav.phases import NavPhase
from polynav.nav.plan_failures import PlanFailures
from polynav.nav.recoveries import (
    BackUp,
    ClearAround,
    ClearCostmap,
    Recovery,
    Rotate,
    Wait,
    ladder_rung,
)
from polynav.nav.replanning import PeriodicReplan
from polynav.nav.retry_budget import RetryBudget
from polynav.planning.errors import NoBodyRoute, PlanningError
from polynav.planning.interface import GlobalPlanner
from polynav.planning.path import Path
from polynav.robot.interface import DockSignals, LaserScan

log = logging.getLogger(__name__)

_SCAN_SETTLE = 0.1
"""[s] the ladder's back-up stands this long first, for a scan to mark again what the clearing
rung before it forgot (a lidar scans at 10-15 Hz)."""

_DRIVING = 0.05
"""[m/s] following its path at least this fast, the robot is not waiting for people (the
patience for them does not run)."""

_REMAINING_SEARCH_WINDOW = 10.0
"""How far ahead [m] along the path the robot's place is searched each period."""

EventSink = Callable[[events.NavigationEvent], None]


_Phase = NavPhase


class Navigator(ChargerPhases, PlanFailures):
    """Drives one navigation attempt at a time on a costmap, with a planner and a controller."""

    def __init__(
        self,
        costmap: Costmap,
        planner: GlobalPlanner,
        controller: Controller,
        progress_checker: ProgressChecker,
        *,
        config: NavigatorConfig | None = None,
        robot_radius: float = 0.25,
        footprint: Footprint | None = None,
        people: PeopleConfig | None = None,
        on_event: EventSink | None = None,
    ) -> None:
        self.config = config or NavigatorConfig()
        self._robot_radius = robot_radius
        self._footprint = footprint or Footprint.circle(robot_radius)
        self._costmap = costmap
        self._planner = planner
        self._replan = PeriodicReplan(planner, reach=self.config.replan_reach,
                                      full_period=self.config.full_replan_period,
                                      watch_for=self.config.people_detour_watch)
        self._controller = controller
        self._progress = progress_checker
        self._sinks: list[EventSink] = [on_event] if on_event else []
        cfg = self.config
        self._rotate = Rotate(costmap, footprint=self._footprint, angle=cfg.recovery_rotate_angle)
        back_up: tuple[Recovery, ...] = (BackUp(
            costmap, distance=cfg.recovery_backup_distance, speed=cfg.recovery_backup_speed,
            robot_radius=robot_radius, footprint=self._footprint, settle=_SCAN_SETTLE,
        ),) if cfg.reverse_allowed else ()
        self._ladder_steps: Sequence[Recovery] = (
            ClearAround(costmap, radius=cfg.recovery_clear_radius),
            *back_up,
            self._rotate,
            Wait(cfg.recovery_wait),
        )
        self._budget = RetryBudget(
            cfg.max_retries, radius=cfg.progress_reset_distance, min_time=cfg.retry_min_time
        )
        self._clear = ClearCostmap(costmap)
        self._passages = ClosedPassages(self._footprint, cfg.passage_time_budget,
                                        limit=cfg.passage_limit,
                                        look_ahead=cfg.passage_look_ahead)
        self._trail = Trail(cfg.recovery_backout_distance + 1.0)
        self._back_out = BackOut(costmap, self._trail, footprint=self._footprint,
                                 max_distance=cfg.recovery_backout_distance,
                                 speed=cfg.recovery_backup_speed,
                                 allowed=cfg.reverse_allowed)
        self._next_id = 1
        self._attempt: NavigationAttempt | None = None
        self._path: Path | None = None
        self._tracked: TrackedPath | None = None
        self._along = 0.0
        self._phase = _Phase.PLAN
        self._phase_since = 0.0
        self._last_plan = 0.0
        self._route_was_open = False
        self._closed_at: list[tuple[float, float]] = []
        self._steered_at: list[tuple[float, float]] = []
        self._cleared_for_plan = False
        self._recovery: Recovery | None = None
        self._hold = Hold(self.config)
        self._last_pose: Pose2D | None = None
        self._last_tick: float | None = None
        self._estimate: LocalizationEstimate | None = None  # the newest, judged at arrival
        # Per attempt: where the robot navigates to (a charger's approach, else the goal), the
        # retry limit, and the charger phases' progress.
        self._target = Pose2D()
        self._undock_origin: Pose2D | None = None
        self._undock_best = 0.0
        self._undock_since = 0.0
        self._undock_retries = 0
        self._dock_since = 0.0
        self._contact_since: float | None = None
        self._scan: LaserScan | None = None
        self._dock_signals: DockSignals | None = None
        self._dock_sight = DockSight(front_reach(self._footprint), self.config.dock_plate)
        self._beacon_seen = False
        # People seen this period, and the current wait for them to make way.
        self._wait = PeopleWait(
            people or PeopleConfig(), costmap, planner, controller, robot_radius=robot_radius,
            footprint=self._footprint,
        )
        self._goal_wait = GoalWait(costmap, patience=cfg.goal_wait, period=cfg.goal_wait_period)
        self._make_way = False  # the pause is a wait in line (pause(make_way=True))

    # -- queries -----------------------------------------------------------------------------

    @property
    def attempt(self) -> NavigationAttempt | None:
        """The current or last attempt, or ``None`` before the first goal."""
        return self._attempt

    @property
    def state(self) -> NavigationState:
        return self._attempt.state if self._attempt else NavigationState.IDLE

    @property
    def path(self) -> Path | None:
        """The path being followed, if any."""
        active = self.state in (NavigationState.RUNNING, NavigationState.PAUSED)
        return self._path if active else None

    def subscribe(self, sink: EventSink) -> None:
        self._sinks.append(sink)

    # -- commands ----------------------------------------------------------------------------

    def start(self, goal: Pose2D, now: float, options: GoalOptions | None = None) -> int:
        """Begin an attempt to reach ``goal`` (map frame); a running attempt is canceled first."""
        if self.state in (NavigationState.RUNNING, NavigationState.PAUSED):
            self.cancel(now)
        options = options or GoalOptions()
        attempt_id = self._next_id
        self._next_id += 1
        phase = Phase.LEAVE_CHARGER if options.undock_distance is not None else Phase.NAVIGATE
        self._attempt = NavigationAttempt(
            attempt_id=attempt_id,
            goal=goal,
            state=NavigationState.RUNNING,
            started_at=now,
            phase=phase,
            options=options,
        )
        self._target = goal
        if options.dock:
            back = self.config.dock_approach
            self._target = Pose2D(
                goal.x - back * math.cos(goal.theta), goal.y - back * math.sin(goal.theta),
                goal.theta,
            )
        self._budget.reset(
            self.config.max_retries if options.max_retries is None else options.max_retries
        )
        self._undock_origin = None
        self._undock_best = 0.0
        self._undock_since = now
        self._undock_retries = 0
        self._contact_since = None
        self._path = None
        self._tracked = None
        self._cleared_for_plan = False
        self._passages.reset()
        self._replan.reset()
        self._closed_at.clear()
        self._steered_at.clear()
        self._back_out.reset()
        self._hold.reset()
        self._last_pose = None
        self._wait.reset()
        self._goal_wait.reset(
            self.config.goal_wait if options.goal_wait is None else options.goal_wait
        )
        self._controller.reset()
        self._controller.set_goal_options(
            yaw_tolerance=options.yaw_tolerance,
            reverse_allowed=options.reverse_allowed and not options.dock,
        )
        self._enter(_Phase.PLAN, now)
        log.info("navigation %d started to (%.2f, %.2f, %.2f)", attempt_id, goal.x, goal.y,
                 goal.theta)
        self._emit(events.NavigationStarted(now, self._attempt))
        if phase is Phase.LEAVE_CHARGER:
            self._emit(events.ChargerLeaveStarted(now, self._require()))
        return attempt_id

    def pause(self, now: float, *, make_way: bool = False) -> bool:
        """Stop and keep the goal; ``False`` if nothing is running.

        ``make_way``: the pause is a wait in line (a passage, a door), not an operator's hold:
        the robot still steps aside for someone it holds up (:meth:`PeopleWait.make_way`)."""
        if self.state is not NavigationState.RUNNING:
            return False
        self._make_way = make_way
        self._update(state=NavigationState.PAUSED)
        self._controller.reset()
        self._wait.pause(now)
        self._emit(events.NavigationPaused(now, self._require()))
        return True

    def resume(self, now: float) -> bool:
        """Continue a paused attempt with a fresh plan; ``False`` if nothing is paused."""
        if self.state is not NavigationState.PAUSED:
            return False
        self._update(state=NavigationState.RUNNING)
        self._wait.resume(now)
        self._enter(_Phase.PLAN, now)
        self._emit(events.NavigationResumed(now, self._require()))
        return True

    def abort(self, reason: FailureReason, message: str, now: float) -> bool:
        """End the attempt as failed for a cause the navigator cannot see (a door on the path
        that never opened); ``False`` if nothing is running or paused."""
        if self.state not in (NavigationState.RUNNING, NavigationState.PAUSED):
            return False
        self._fail(reason, message, now)
        return True

    def cancel(self, now: float) -> bool:
        """End the attempt as canceled; ``False`` if nothing is running or paused."""
        if self.state not in (NavigationState.RUNNING, NavigationState.PAUSED):
            return False
        self._finish(NavigationState.CANCELED, now)
        return True

    # -- the control period ------------------------------------------------------------------

    def tick(
        self,
        now: float,
        estimate: LocalizationEstimate,
        velocity: Twist,
        estop: bool,
        *,
        charging: bool = False,
        people: PeopleView | None = None,
        scan: LaserScan | None = None,
        dock: DockSignals | None = None,
    ) -> Twist:
        """Advance the attempt by one control period; returns the velocity to command.

        ``charging``: the charger contacts carry current (docking ends on it). ``people``: the
        people seen now, in the map frame. ``scan``: a scan new since the last period (the
        dock phase looks for the charger in it); ``dock``: the base's docking sensors, if any.
        """
        dt = 0.0 if self._last_tick is None else max(0.0, now - self._last_tick)
        self._last_tick = now
        self._wait.people = people if people is not None else PeopleView()
        if (self.state is NavigationState.PAUSED and self._make_way and not estop
                and estimate.state is LocalizationState.TRACKING):
            return self._wait.make_way(estimate.pose, velocity, now, dt)
        if self.state is not NavigationState.RUNNING:
            return Twist()
        pose, self._estimate = estimate.pose, estimate
        self._scan, self._dock_signals = scan, dock
        self._track_distance(pose)
        phase = self._require().phase
        if phase is Phase.LEAVE_CHARGER:
            return self._tick_undock(pose, now, estop)
        if phase is Phase.DOCK:
            return self._tick_dock(pose, now, estop, charging)
        if self._held(now, estimate, estop):
            return Twist()
        if self._phase is _Phase.RECOVER:
            twist = self._tick_recovery(pose, now)
            if twist is not None:
                return self._wait.slow(pose, twist)  # backing up into someone is no recovery
        if self._phase is _Phase.GOAL_WAIT:
            step = self._goal_wait.tick(pose, now, self._plan_path)
            if step.expired:
                self._fail(FailureReason.GOAL_OCCUPIED,
                           f"the goal stayed occupied for {self._goal_wait.patience:g} s", now)
            elif step.path is not None:
                self._follow_plan(step.path, pose, now)
            return Twist()
        if self._phase is _Phase.WAIT:
            step = self._wait.tick(pose, velocity, now, dt, self._path, self._plan_path)
            if step.expired:
                self._fail(FailureReason.BLOCKED_BY_PERSON,
                           f"people blocked the way for {self._wait.config.patience:g} s", now)
                return Twist()
            if step.path is not None:
                self._replan.watch(now)
                self._set_path(step.path, now)
                self._progress.reset(pose, now)
                self._enter(_Phase.FOLLOW, now)
            elif step.go_on:
                self._enter(_Phase.PLAN, now)
            else:
                return step.twist
        if self._phase is _Phase.BLOCKED:
            if now - self._phase_since < self.config.blocked_wait:
                return Twist()
            if self._wait.blocks(pose, self._path):
                self._wait_for_people(pose, now)
                return Twist()
            self._on_blocked(pose, now)
            # Failed, recovering or re-planning: that starts with the next period.
            return Twist()
        if self._phase is _Phase.PLAN:
            if not self._plan(pose, now):
                return Twist()
        elif (
            now - self._last_plan >= self.config.replan_period
            or self._route_closed_since_plan(now)
        ) and self._remaining(pose) > self.config.replan_min_remaining:
            self._replan_quietly(pose, now)
        return self._follow(pose, velocity, now, dt)

    # -- phases ------------------------------------------------------------------------------

    def _held(self, now: float, estimate: LocalizationEstimate, estop: bool) -> bool:
        step = self._hold.tick(now, estop=estop, lost=estimate.state is LocalizationState.LOST)
        if step.released is not None:
            self._emit(events.NavigationReleased(now, self._require(), cause=step.released))
            self._controller.reset()
            self._enter(_Phase.PLAN, now)
        if step.began is not None:
            self._controller.reset()
            self._emit(events.NavigationHeld(now, self._require(), cause=step.began))
        if step.expired is not None:
            self._fail(step.expired, step.message, now)
        return step.held

    def _plan(self, pose: Pose2D, now: float) -> bool:
        try:
            path = self._plan_path(pose)
        except PlanningError as exc:
            self._on_plan_error(exc, pose, now)
            return False
        self._follow_plan(path, pose, now)
        return True

    def _follow_plan(self, path: Path, pose: Pose2D, now: float) -> None:
        """Follow a whole-way plan from here (the plan phase's, or one found in the goal wait)."""
        self._replan.whole_way_planned(now)
        self._set_path(path, now)
        self._progress.reset(pose, now)
        self._enter(_Phase.FOLLOW, now)

    def _plan_path(self, pose: Pose2D) -> Path:
        self._passages.refresh(self._costmap, self._last_tick or 0.0)
        try:
            return self._planner.plan(
                self._passages.planning_grid(self._costmap.planning_costs(), pose), pose,
                self._target,
                goal_tolerance=self._require().options.near_tolerance,
            )
        except NoBodyRoute as exc:
            if not touches_marks(self._costmap, self._footprint, exc.blocked_at):
                raise
            # What closes the body's way is the lidar's marks, not the building: a person's
            # trail, a trolley. Take the disk's route; the controller stops if it must.
            log.info("no route for the body past marks at (%.2f, %.2f): the grid route",
                     exc.blocked_at.x, exc.blocked_at.y)
            return exc.route

    def _replan_quietly(self, pose: Pose2D, now: float) -> None:
        """A periodic re-plan, with hysteresis: the current route stays unless it is blocked or
        the new one is clearly shorter. On failure the old path is kept too; the controller
        still guards it."""
        self._last_plan = now
        remaining = self._remaining(pose)
        try:
            self._passages.refresh(self._costmap, now)
            path = self._replan.plan(
                self._passages.planning_grid(self._costmap.planning_costs(), pose), pose,
                self._target,
                self._tracked, self._along, now,
                goal_tolerance=self._require().options.near_tolerance,
            )
        except PlanningError as exc:
            log.debug("periodic re-plan failed, keeping the path: %s", exc)
            return
        if self._tracked is not None:
            blocked = route_choice.route_blocked(self._costmap, self._tracked, self._along)
            if not blocked:
                # Lengths as the time the controller takes over them (route_choice).
                off_route = remaining - (self._tracked.length - self._along)
                remaining = off_route + self._drive_length(self._tracked, self._along)
                new_length = self._drive_length(TrackedPath.from_points(path.points), 0.0)
                if not route_choice.clearly_shorter(
                    remaining=remaining, new_length=new_length,
                    hysteresis=self.config.replan_hysteresis,
                    min_gain=self.config.replan_min_gain,
                ):
                    log.debug("re-plan: keeping the route (%.2f m left, new %.2f m, as driven)",
                              remaining, new_length)
                    return
            if blocked and self._wait.blocks(pose, self._path):
                self._replan.watch(now)  # people closed it: they may soon open it again
        self._set_path(path, now)

    def _drive_length(self, route: TrackedPath, along: float) -> float:
        cfg = self.config
        return route_choice.drive_length(
            self._costmap, self._footprint, route, along,
            open_clearance=cfg.route_open_clearance, least_clearance=cfg.route_least_clearance)

    def _route_closed_since_plan(self, now: float) -> bool:
        """Has the lidar closed the route ahead since it was planned open?

        Waiting for the periodic re-plan, a robot drives on into the pocket or the wall it has
        just seen, stops before it, waits, turns round and starts again; re-planned at once it
        bends round while still moving. A route planned through cells already closed (a body
        route through an inscribed gap) does not count: re-planning it would give it again.
        """
        if (
            not self._route_was_open
            or self._tracked is None
            or now - self._last_plan < self.config.closed_route_replan_period
        ):
            return False
        closed = route_choice.first_blocked(self._costmap, self._tracked, self._along)
        if closed is None:
            return False
        self._route_was_open = False
        # Once per place: a mark flickering on the inscribed ring of a post the route grazes
        # would have every new route closed again half a second later, and the robot turning
        # between them (demo, lattice course 92: 55 plans, 57 s turning, timed out).
        if any(math.hypot(closed[0] - x, closed[1] - y) < route_choice.CLOSED_ROUTE_PLACE
               for x, y in self._closed_at):
            return False
        self._closed_at.append(closed)
        log.info("the route ahead was closed at (%.2f, %.2f) since it was planned: re-planning "
                 "now", *closed)
        return True

    def _follow(self, pose: Pose2D, velocity: Twist, now: float, dt: float) -> Twist:
        command = self._controller.compute(pose, velocity, self._costmap, dt)
        self._update(distance_remaining=self._remaining(pose))
        options = self._require().options
        if command.status is ControlStatus.ARRIVED or (
            options.pass_tolerance is not None
            and not options.dock
            and pose.distance_to(self._target) <= options.pass_tolerance
        ):
            self._arrived(now)
            return Twist()
        near = options.near_tolerance
        if (
            command.status is ControlStatus.BLOCKED
            and near is not None
            and not options.dock
            and pose.distance_to(self._target) <= near
        ):
            log.info("blocked %.2f m from the goal, within its tolerance: done",
                     pose.distance_to(self._target))
            self._arrived(now)
            return Twist()
        if command.status is ControlStatus.BLOCKED:
            self._passages.note_block(self._costmap, self._tracked, self._along, pose)
            if self._steer_round(pose, now):
                return Twist()  # braking for one period; the new route from the next
            self._enter(_Phase.BLOCKED, now)
            self._emit(events.NavigationBlocked(now, self._require()))
            return Twist()
        if command.status is not ControlStatus.ROTATING and not self._progress.check(pose, now):
            self._retry("stuck", pose, now)
            return Twist()
        reset = self.config.progress_reset_distance
        if command.twist.linear > 0.0:
            self._trail.record(pose)
        self._budget.moved(pose, self._to_goal(pose))
        self._wait.moved(pose, reset)
        twist = self._wait.slow(pose, command.twist, now)
        if abs(velocity.linear) >= _DRIVING:
            self._wait.drove(dt)  # the last period on the path: not waiting for people
        if self._wait.held(now):  # people stand where the robot would go: wait for them
            self._wait_for_people(pose, now)
            return Twist()
        return twist

    def _retry(self, cause: str, pose: Pose2D, now: float) -> None:
        """Count a failure at this place; give up when the place is exhausted (see
        :mod:`~polynav.nav.retry_budget`), else climb the recovery ladder and re-plan."""
        rung = self._budget.record(pose, self._to_goal(pose), now)
        self._update(retries=self._require().retries + 1)
        if self._budget.exhausted(now):
            reason = FailureReason.STUCK
            tried = self._passages.tried
            named = f"; passages tried at {', '.join(tried)}" if tried else ""
            self._fail(reason, f"{cause} after {self._budget.max_retries} retries{named}", now)
            return
        self._controller.reset()
        self._rotate.toward = (self._target.x, self._target.y)
        recovery = ladder_rung(self._ladder_steps, rung)
        self._emit_retry(cause, recovery.name, now)
        self._recovery = recovery
        recovery.start(pose, now)
        self._enter(_Phase.RECOVER, now)

    def _to_goal(self, pose: Pose2D) -> float:
        return math.hypot(self._target.x - pose.x, self._target.y - pose.y)

    def _tick_recovery(self, pose: Pose2D, now: float) -> Twist | None:
        assert self._recovery is not None
        twist = self._recovery.tick(pose, now)
        if twist is None:
            self._recovery = None
            self._enter(_Phase.PLAN, now)
        return twist

    def _wait_for_people(self, pose: Pose2D, now: float) -> None:
        if self._wait.begin(pose, now):
            self._emit(events.NavigationWaiting(now, self._require(), cause="person"))
        self._enter(_Phase.WAIT, now)

    # -- bookkeeping -------------------------------------------------------------------------

    def _charger_left(self, now: float) -> None:
        self._enter(_Phase.PLAN, now)

    def _set_path(self, path: Path, now: float) -> None:
        # A way was found: an earlier "no path" is history, and the next one (the marks a
        # walker left in a door, say) is cleared once more before it is final.
        self._cleared_for_plan = False
        open_doors_on(self._costmap, path)
        self._path = path
        self._tracked = TrackedPath.from_points(path.points)
        self._along = 0.0
        self._last_plan = now
        self._route_was_open = not route_choice.route_blocked(self._costmap, self._tracked, 0.0)
        end = path.points[-1]
        target = self._target
        if math.hypot(end[0] - target.x, end[1] - target.y) > 1e-6:
            # The planner ends exactly on the goal, or on a substitute cell near an occupied
            # goal (near_tolerance): then the robot ends there.
            target = Pose2D(float(end[0]), float(end[1]), target.theta)
        self._controller.set_path(path, target)
        self._update(plans=self._require().plans + 1)
        self._emit(events.PathPlanned(now, self._require(), length=path.length))

    def _remaining(self, pose: Pose2D) -> float:
        """Path length [m] from the point nearest the robot to the goal."""
        if self._tracked is None:
            return pose.distance_to(self._target)
        # Search forward from the last place only: the robot moves along the path.
        self._along = self._tracked.project(
            pose.x, pose.y, start=self._along, window=_REMAINING_SEARCH_WINDOW
        )
        px, py = self._tracked.point_at(self._along)
        return self._tracked.length - self._along + float(np.hypot(px - pose.x, py - pose.y))

    def _track_distance(self, pose: Pose2D) -> None:
        if self._last_pose is not None:
            step = pose.distance_to(self._last_pose)
            self._update(distance_travelled=self._require().distance_travelled + step)
        self._last_pose = pose

    def _enter(self, phase: _Phase, now: float) -> None:
        self._phase = phase
        self._phase_since = now

    def _fail(self, reason: FailureReason, message: str, now: float) -> None:
        self._update(reason=reason, message=message)
        self._finish(NavigationState.FAILED, now)

    def _finish(self, state: NavigationState, now: float) -> None:
        self._update(state=state, ended_at=now)
        self._controller.reset()
        self._recovery = None
        attempt = self._require()
        log.info("navigation %d %s%s", attempt.attempt_id, state.value,
                 f" ({attempt.reason.value}: {attempt.message})" if attempt.reason else "")
        event_type: type[events.NavigationEvent] = {
            NavigationState.SUCCEEDED: events.NavigationSucceeded,
            NavigationState.FAILED: events.NavigationFailed,
            NavigationState.CANCELED: events.NavigationCanceled,
        }[state]
        self._emit(event_type(now, attempt))

    def _emit_retry(self, cause: str, recovery: str, now: float) -> None:
        log.warning("navigation retry after %s: %s", cause, recovery or "re-plan")
        self._emit(events.NavigationRetry(now, self._require(), cause=cause, recovery=recovery))

    def _update(self, **changes: object) -> None:
        self._attempt = replace(self._require(), **changes)  # type: ignore[arg-type]

    def _require(self) -> NavigationAttempt:
        assert self._attempt is not None
        return self._attempt

    def _emit(self, event: events.NavigationEvent) -> None:
        for sink in self._sinks:
            sink(event)
