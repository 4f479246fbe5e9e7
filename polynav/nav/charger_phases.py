"""The charger phases of a navigation attempt: backing off a charger, and docking onto one.

A mixin over :class:`~polynav.nav.navigator.Navigator` (the navigator stays one class to its
users; the charger's state machine lives here, apart from planning and recovering). A robot
standing on a charger first backs straight off it (*leave charger*, retried when it makes no
headway for ``undock_retry_after`` seconds, failed after ``undock_max_retries``), and a goal that
is a charger is reached at its approach pose, from where the robot drives straight onto the
contacts and waits for charging current (*dock*).
"""

from __future__ import annotations

import logging
import math
from typing import TYPE_CHECKING

from polynav.control.interface import Controller
from polynav.geometry import Pose2D, Twist, angle_diff
from polynav.localization.interface import LocalizationEstimate
from polynav.maps import costs as cost_values
from polynav.maps.costmap import Costmap
from polynav.nav import arrival, events
from polynav.nav.attempt import FailureReason, NavigationAttempt, NavigationState, Phase

if TYPE_CHECKING:
    from polynav.nav.navigator_config import NavigatorConfig

log = logging.getLogger(__name__)


class ChargerPhases:
    """Leave-charger and dock phases; mixed into the navigator, whose state it shares."""

    config: NavigatorConfig
    _costmap: Costmap
    _controller: Controller
    _robot_radius: float
    _undock_origin: Pose2D | None
    _undock_best: float
    _undock_since: float
    _undock_retries: int
    _dock_since: float
    _contact_since: float | None
    _estimate: LocalizationEstimate | None

    if TYPE_CHECKING:

        def _require(self) -> NavigationAttempt: ...

        def _update(self, **changes: object) -> None: ...

        def _emit(self, event: events.NavigationEvent) -> None: ...

        def _fail(self, reason: FailureReason, message: str, now: float) -> None: ...

        def _finish(self, state: NavigationState, now: float) -> None: ...

        def _charger_left(self, now: float) -> None: ...


    def _arrived(self, now: float) -> None:
        """At the navigation target: done, or at a charger's approach: dock; either only when
        the pose is known as precisely as the goal demands (:mod:`~polynav.nav.arrival`)."""
        options = self._require().options
        self._record_uncertainty()
        verdict = arrival.judge(options, self._estimate)
        if not verdict.ok:
            log.warning("navigation %d: arrived, but %s", self._require().attempt_id,
                        verdict.message)
            self._fail(FailureReason.NOT_LOCALIZED, verdict.message, now)
            return
        if not options.dock:
            self._finish(NavigationState.SUCCEEDED, now)
            return
        self._controller.reset()
        self._update(phase=Phase.DOCK, distance_remaining=self.config.dock_approach)
        self._dock_since = now
        self._contact_since = None
        log.info("navigation %d: at the charger's approach, docking", self._require().attempt_id)
        self._emit(events.DockingStarted(now, self._require()))

    def _record_uncertainty(self) -> None:
        estimate = self._estimate
        self._update(arrival_uncertainty=None if estimate is None else estimate.uncertainty)

    def _tick_undock(self, pose: Pose2D, now: float, estop: bool) -> Twist:
        """Back straight off the charger; no headway for a while is a retry, too many fail."""
        cfg = self.config
        options = self._require().options
        assert options.undock_distance is not None
        if self._undock_origin is None:
            self._undock_origin = pose
        moved = pose.distance_to(self._undock_origin)
        if moved >= options.undock_distance:
            self._update(phase=Phase.NAVIGATE)
            self._charger_left(now)
            log.info("left the charger after %.2f m", moved)
            self._emit(events.ChargerLeft(now, self._require()))
            return Twist()
        if moved > self._undock_best + 0.02:
            self._undock_best = moved
            self._undock_since = now
        elif now - self._undock_since >= cfg.undock_retry_after:
            self._undock_retries += 1
            self._undock_since = now
            if self._undock_retries > cfg.undock_max_retries:
                self._emit(events.ChargerLeaveFailed(now, self._require()))
                self._fail(FailureReason.UNDOCK_FAILED, "could not leave the charger", now)
                return Twist()
            log.warning("no headway off the charger: retry %d", self._undock_retries)
            self._emit(events.ChargerLeaveRetry(now, self._require(), retries=self._undock_retries))
        if estop or not self._free_behind(pose):
            return Twist()
        return Twist(-cfg.undock_speed, 0.0)

    def _free_behind(self, pose: Pose2D) -> bool:
        reach = self._robot_radius + 0.1
        x = pose.x - reach * math.cos(pose.theta)
        y = pose.y - reach * math.sin(pose.theta)
        return self._costmap.cost_at(x, y) < cost_values.LETHAL

    def _tick_dock(self, pose: Pose2D, now: float, estop: bool, charging: bool) -> Twist:
        """Drive straight onto the charger's pose, then wait for charging current."""
        cfg = self.config
        attempt = self._require()
        if charging:
            self._record_uncertainty()
            self._emit(events.DockingSucceeded(now, self._require()))
            self._update(distance_remaining=0.0)
            self._finish(NavigationState.SUCCEEDED, now)
            return Twist()
        if now - self._dock_since >= cfg.dock_timeout:
            return self._dock_failed("timeout", now)
        goal = attempt.goal
        dx, dy = goal.x - pose.x, goal.y - pose.y
        cos_g, sin_g = math.cos(goal.theta), math.sin(goal.theta)
        along = dx * cos_g + dy * sin_g
        lateral = -dx * sin_g + dy * cos_g
        self._update(distance_remaining=max(0.0, along))
        if along <= 0.01:
            if self._contact_since is None:
                self._contact_since = now
            elif now - self._contact_since >= cfg.dock_contact_wait:
                return self._dock_failed("no_contact", now)
            return Twist()
        if estop:
            return Twist()
        speed = min(cfg.dock_speed, max(0.03, along))
        turn = 1.5 * angle_diff(goal.theta, pose.theta) + 4.0 * lateral
        return Twist(speed, max(-0.4, min(0.4, turn)))

    def _dock_failed(self, cause: str, now: float) -> Twist:
        log.warning("docking failed: %s", cause)
        self._emit(events.DockingFailed(now, self._require(), cause=cause))
        self._fail(FailureReason.DOCK_FAILED, f"docking failed: {cause}", now)
        return Twist()
