"""The navigator: one goal at a time, from plan to arrival, with retries, recoveries and events.

The navigator is a service (DESIGN §1): it owns no thread and reads no clock. The runtime calls
:meth:`Navigator.tick` once per control period with the time, the localization estimate, the
measured velocity and the e-stop state, and commands the returned velocity to the base.

Inside a running attempt the navigator moves between phases:

- *plan*: plan from the estimated pose to the goal on the live costmap;
- *follow*: the controller tracks the path; the path is re-planned every ``replan_period`` so
  new obstacles are routed around before the controller has to stop for them;
- *blocked*: the controller stopped in front of an obstacle; wait ``blocked_wait`` (a person
  usually walks on), then re-plan;
- *recover*: a recovery behaviour runs (clear costmap, spin, back up) before the next plan.

Each failure counts as a retry; ``max_retries`` failures in a row without the robot getting
anywhere end the attempt with a :class:`FailureReason`. An e-stop or lost localization holds the
robot without ending the attempt; it resumes with a fresh plan when the hold is released.
"""

from __future__ import annotations

import enum
import logging
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

import numpy as np

from polynav.control.interface import Controller, ControlStatus
from polynav.control.progress_checker import ProgressChecker
from polynav.control.tracked_path import TrackedPath
from polynav.errors import ConfigError
from polynav.geometry import Pose2D, Twist
from polynav.localization.interface import LocalizationEstimate, LocalizationState
from polynav.maps.costmap import Costmap
from polynav.nav import events
from polynav.nav.attempt import FailureReason, NavigationAttempt, NavigationState
from polynav.nav.recoveries import BackUp, ClearCostmap, Recovery, Spin
from polynav.planning.errors import GoalOccupied, NoPath, OutsideMap, PlanningError, StartOccupied
from polynav.planning.interface import GlobalPlanner
from polynav.planning.path import Path

log = logging.getLogger(__name__)

_REMAINING_SEARCH_WINDOW = 10.0
"""How far ahead [m] along the path the robot's place is searched each period."""

EventSink = Callable[[events.NavigationEvent], None]


@dataclass(frozen=True, slots=True)
class NavigatorConfig:
    """Timing and retry policy of the navigator [s, m]."""

    replan_period: float = 3.0
    replan_min_remaining: float = 1.0
    blocked_wait: float = 1.5
    max_retries: int = 4
    progress_reset_distance: float = 1.0
    localization_grace: float = 5.0
    estop_fail_after: float | None = None

    def __post_init__(self) -> None:
        for key in ("replan_period", "blocked_wait", "localization_grace"):
            if getattr(self, key) <= 0.0:
                raise ConfigError(f"nav.navigator.{key}", "must be > 0")
        if self.replan_min_remaining < 0.0:
            raise ConfigError("nav.navigator.replan_min_remaining", "must be >= 0")
        if self.progress_reset_distance <= 0.0:
            raise ConfigError("nav.navigator.progress_reset_distance", "must be > 0")
        if self.max_retries < 0:
            raise ConfigError("nav.navigator.max_retries", "must be >= 0")
        if self.estop_fail_after is not None and self.estop_fail_after <= 0.0:
            raise ConfigError("nav.navigator.estop_fail_after", "must be > 0 or None")


class _Phase(enum.Enum):
    PLAN = "plan"
    FOLLOW = "follow"
    BLOCKED = "blocked"
    RECOVER = "recover"


class Navigator:
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
        on_event: EventSink | None = None,
    ) -> None:
        self.config = config or NavigatorConfig()
        self._costmap = costmap
        self._planner = planner
        self._controller = controller
        self._progress = progress_checker
        self._sinks: list[EventSink] = [on_event] if on_event else []
        self._stuck_recoveries: Sequence[Recovery] = (
            ClearCostmap(costmap),
            Spin(),
            BackUp(costmap, robot_radius=robot_radius),
        )
        self._clear = ClearCostmap(costmap)
        self._next_id = 1
        self._attempt: NavigationAttempt | None = None
        self._path: Path | None = None
        self._tracked: TrackedPath | None = None
        self._along = 0.0
        self._phase = _Phase.PLAN
        self._phase_since = 0.0
        self._last_plan = 0.0
        self._failures = 0
        self._failure_pose: Pose2D | None = None
        self._cleared_for_plan = False
        self._recovery: Recovery | None = None
        self._recovery_index = 0
        self._hold: str | None = None
        self._hold_since = 0.0
        self._last_pose: Pose2D | None = None
        self._last_tick: float | None = None

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

    def start(self, goal: Pose2D, now: float) -> int:
        """Begin an attempt to reach ``goal`` (map frame); a running attempt is canceled first."""
        if self.state in (NavigationState.RUNNING, NavigationState.PAUSED):
            self.cancel(now)
        attempt_id = self._next_id
        self._next_id += 1
        self._attempt = NavigationAttempt(
            attempt_id=attempt_id, goal=goal, state=NavigationState.RUNNING, started_at=now
        )
        self._path = None
        self._tracked = None
        self._failures = 0
        self._failure_pose = None
        self._cleared_for_plan = False
        self._recovery_index = 0
        self._hold = None
        self._last_pose = None
        self._controller.reset()
        self._enter(_Phase.PLAN, now)
        log.info("navigation %d started to (%.2f, %.2f, %.2f)", attempt_id, goal.x, goal.y,
                 goal.theta)
        self._emit(events.NavigationStarted(now, self._attempt))
        return attempt_id

    def pause(self, now: float) -> bool:
        """Stop and keep the goal; ``False`` if nothing is running."""
        if self.state is not NavigationState.RUNNING:
            return False
        self._update(state=NavigationState.PAUSED)
        self._controller.reset()
        self._emit(events.NavigationPaused(now, self._require()))
        return True

    def resume(self, now: float) -> bool:
        """Continue a paused attempt with a fresh plan; ``False`` if nothing is paused."""
        if self.state is not NavigationState.PAUSED:
            return False
        self._update(state=NavigationState.RUNNING)
        self._enter(_Phase.PLAN, now)
        self._emit(events.NavigationResumed(now, self._require()))
        return True

    def cancel(self, now: float) -> bool:
        """End the attempt as canceled; ``False`` if nothing is running or paused."""
        if self.state not in (NavigationState.RUNNING, NavigationState.PAUSED):
            return False
        self._finish(NavigationState.CANCELED, now)
        return True

    # -- the control period ------------------------------------------------------------------

    def tick(
        self, now: float, estimate: LocalizationEstimate, velocity: Twist, estop: bool
    ) -> Twist:
        """Advance the attempt by one control period; returns the velocity to command."""
        dt = 0.0 if self._last_tick is None else max(0.0, now - self._last_tick)
        self._last_tick = now
        if self.state is not NavigationState.RUNNING:
            return Twist()
        pose = estimate.pose
        self._track_distance(pose)
        if self._held(now, estimate, estop):
            return Twist()
        if self._phase is _Phase.RECOVER:
            twist = self._tick_recovery(pose, now)
            if twist is not None:
                return twist
        if self._phase is _Phase.BLOCKED:
            if now - self._phase_since < self.config.blocked_wait:
                return Twist()
            self._retry("blocked", pose, now)
            if self.state is not NavigationState.RUNNING:
                return Twist()
        if self._phase is _Phase.PLAN:
            if not self._plan(pose, now):
                return Twist()
        elif (
            now - self._last_plan >= self.config.replan_period
            and self._remaining(pose) > self.config.replan_min_remaining
        ):
            self._replan_quietly(pose, now)
        return self._follow(pose, velocity, now, dt)

    # -- phases ------------------------------------------------------------------------------

    def _held(self, now: float, estimate: LocalizationEstimate, estop: bool) -> bool:
        cause = None
        if estop:
            cause = "e-stop"
        elif estimate.state is LocalizationState.LOST:
            cause = "localization lost"
        if cause is None:
            if self._hold is not None:
                log.info("navigation hold released (%s)", self._hold)
                self._emit(events.NavigationReleased(now, self._require(), cause=self._hold))
                self._hold = None
                self._controller.reset()
                self._enter(_Phase.PLAN, now)
            return False
        if self._hold != cause:
            log.warning("navigation held: %s", cause)
            self._hold = cause
            self._hold_since = now
            self._controller.reset()
            self._emit(events.NavigationHeld(now, self._require(), cause=cause))
        held_for = now - self._hold_since
        if cause == "localization lost" and held_for >= self.config.localization_grace:
            self._fail(FailureReason.LOCALIZATION_LOST, "localization lost for too long", now)
        elif (
            cause == "e-stop"
            and self.config.estop_fail_after is not None
            and held_for >= self.config.estop_fail_after
        ):
            self._fail(FailureReason.ESTOP, "e-stop held for too long", now)
        return True

    def _plan(self, pose: Pose2D, now: float) -> bool:
        goal = self._require().goal
        try:
            path = self._planner.plan(self._costmap, pose, goal)
        except PlanningError as exc:
            self._on_plan_error(exc, pose, now)
            return False
        self._set_path(path, now)
        self._cleared_for_plan = False
        self._progress.reset(pose, now)
        self._enter(_Phase.FOLLOW, now)
        return True

    def _on_plan_error(self, exc: PlanningError, pose: Pose2D, now: float) -> None:
        log.warning("planning failed: %s", exc)
        if isinstance(exc, OutsideMap):
            self._fail(FailureReason.NO_PATH, f"outside the map: {exc}", now)
        elif isinstance(exc, (NoPath, GoalOccupied)):
            # Marks from the lidar may be what closes the way; with them cleared only the map
            # and the keepouts decide, and a second failure is final.
            reason = (
                FailureReason.NO_PATH if isinstance(exc, NoPath) else FailureReason.GOAL_OCCUPIED
            )
            if self._cleared_for_plan:
                self._fail(reason, str(exc) or reason.value, now)
            else:
                self._cleared_for_plan = True
                self._clear.start(pose, now)
                self._emit_retry(reason.value, self._clear.name, now)
        elif isinstance(exc, StartOccupied):
            self._retry("start occupied", pose, now)
        else:
            self._fail(FailureReason.NO_PATH, str(exc), now)

    def _replan_quietly(self, pose: Pose2D, now: float) -> None:
        """A periodic re-plan: on failure keep the old path, the controller still guards it."""
        self._last_plan = now
        try:
            path = self._planner.plan(self._costmap, pose, self._require().goal)
        except PlanningError as exc:
            log.debug("periodic re-plan failed, keeping the path: %s", exc)
            return
        self._set_path(path, now)

    def _follow(self, pose: Pose2D, velocity: Twist, now: float, dt: float) -> Twist:
        command = self._controller.compute(pose, velocity, self._costmap, dt)
        self._update(distance_remaining=self._remaining(pose))
        if command.status is ControlStatus.ARRIVED:
            self._finish(NavigationState.SUCCEEDED, now)
            return Twist()
        if command.status is ControlStatus.BLOCKED:
            self._enter(_Phase.BLOCKED, now)
            self._emit(events.NavigationBlocked(now, self._require()))
            return Twist()
        if command.status is not ControlStatus.ROTATING and not self._progress.check(pose, now):
            self._retry("stuck", pose, now)
            return Twist()
        if self._failure_pose is not None and (
            pose.distance_to(self._failure_pose) >= self.config.progress_reset_distance
        ):
            self._failures = 0
            self._failure_pose = None
        return command.twist

    def _retry(self, cause: str, pose: Pose2D, now: float) -> None:
        """Count a failure; give up after too many in a row, else recover and re-plan."""
        self._failures += 1
        self._failure_pose = pose
        self._update(retries=self._require().retries + 1)
        if self._failures > self.config.max_retries:
            reason = FailureReason.STUCK
            self._fail(reason, f"{cause} after {self.config.max_retries} retries", now)
            return
        self._controller.reset()
        if cause == "blocked":
            self._emit_retry(cause, "re-plan", now)
            self._enter(_Phase.PLAN, now)
            return
        recovery = self._stuck_recoveries[self._recovery_index % len(self._stuck_recoveries)]
        self._recovery_index += 1
        self._emit_retry(cause, recovery.name, now)
        self._recovery = recovery
        recovery.start(pose, now)
        self._enter(_Phase.RECOVER, now)

    def _tick_recovery(self, pose: Pose2D, now: float) -> Twist | None:
        assert self._recovery is not None
        twist = self._recovery.tick(pose, now)
        if twist is None:
            self._recovery = None
            self._enter(_Phase.PLAN, now)
        return twist

    # -- bookkeeping -------------------------------------------------------------------------

    def _set_path(self, path: Path, now: float) -> None:
        self._path = path
        self._tracked = TrackedPath.from_points(path.points)
        self._along = 0.0
        self._last_plan = now
        self._controller.set_path(path, self._require().goal)
        self._emit(events.PathPlanned(now, self._require(), length=path.length))

    def _remaining(self, pose: Pose2D) -> float:
        """Path length [m] from the point nearest the robot to the goal."""
        if self._tracked is None:
            return pose.distance_to(self._require().goal)
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
