"""The charger phases of a navigation attempt: backing off a charger, and docking onto one.

A mixin over :class:`~polynav.nav.navigator.Navigator` (the navigator stays one class to its
users; the charger's state machine lives here, apart from planning and recovering). A robot
standing on a charger first backs straight off it (*leave charger*, retried when it makes no
headway for ``undock_retry_after`` seconds, failed after ``undock_max_retries``), and a goal that
is a charger is reached at its approach pose, from where the robot drives straight onto the
contacts and waits for charging current (*dock*).

Docking goes by what the robot sees, as Nav2's docking server does: at the approach the robot
stands and looks for the charger's plate near the marker (:mod:`~polynav.nav.dock_sight`) and,
with a beacon receiver, for its infrared beacon; neither within ``dock_find_wait`` fails the dock
(``no_feature``, ``no_infrared``). The final approach then aims at the plate as seen, re-detected
at every scan, so a marker some centimetres and degrees off the charger still docks. On the
contacts, a data link whose frames never check (``bad_data``) or no current (``no_contact``)
fails it after ``dock_contact_wait``.
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
from polynav.nav.dock_sight import DockSight
from polynav.robot.interface import DockLink, DockSignals, LaserScan

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
    _scan: LaserScan | None
    _dock_signals: DockSignals | None
    _dock_sight: DockSight
    _beacon_seen: bool

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
        self._beacon_seen = False
        self._dock_sight.reset(self._require().goal)
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
        """Find the charger, drive straight onto it as seen, then wait for charging current."""
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
        signals = self._dock_signals
        if signals is not None and signals.beacon:
            self._beacon_seen = True
        goal = attempt.goal
        if cfg.dock_by_sight:
            sight = self._dock_sight
            if self._scan is not None:
                sight.see(self._scan, pose)
            seen = sight.docked_pose
            if seen is None or (signals is not None and not self._beacon_seen):
                if now - self._dock_since < cfg.dock_find_wait:
                    return Twist()  # stand and look
                return self._dock_failed("no_feature" if seen is None else "no_infrared", now)
            goal = seen
        elif signals is not None and not self._beacon_seen:
            if now - self._dock_since < cfg.dock_find_wait:
                return Twist()
            return self._dock_failed("no_infrared", now)
        dx, dy = goal.x - pose.x, goal.y - pose.y
        cos_g, sin_g = math.cos(goal.theta), math.sin(goal.theta)
        along = dx * cos_g + dy * sin_g
        lateral = -dx * sin_g + dy * cos_g
        self._update(distance_remaining=max(0.0, along))
        if along <= 0.01:
            if self._contact_since is None:
                self._contact_since = now
            elif now - self._contact_since >= cfg.dock_contact_wait:
                bad_link = signals is not None and signals.link is DockLink.INVALID
                return self._dock_failed("bad_data" if bad_link else "no_contact", now)
            return Twist()
        if estop:
            return Twist()
        speed = min(cfg.dock_speed, max(0.03, along))
        turn = _HEADING_GAIN * angle_diff(goal.theta, pose.theta) + _LATERAL_GAIN * lateral
        return Twist(speed, max(-_MAX_TURN, min(_MAX_TURN, turn)))

    def _dock_failed(self, cause: str, now: float) -> Twist:
        detail = _DOCK_FAILURES.get(cause, "")
        message = f"docking failed: {cause}" + (f" ({detail})" if detail else "")
        log.warning("%s", message)
        self._emit(events.DockingFailed(now, self._require(), cause=cause))
        self._fail(FailureReason.DOCK_FAILED, message, now)
        return Twist()


# The final approach's steering onto the dock's axis: at the dock speed (0.1 m/s) a lateral
# offset decays critically damped in about a second (natural frequency sqrt(v * lateral gain),
# heading gain twice that), so 9 cm off the axis at the approach is under 1 cm at the contacts.
_HEADING_GAIN = 2.5
_LATERAL_GAIN = 16.0
_MAX_TURN = 0.6

_DOCK_FAILURES = {
    "no_feature": "no charger's plate in the scan near the charger point",
    "no_infrared": "the charger's infrared beacon is not seen",
    "bad_data": "the charger's data link gives no valid frame",
    "no_contact": "no charging current on the contacts",
}
