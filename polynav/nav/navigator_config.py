"""The navigator's timing and retry policy: how long it waits, how often it re-plans, when it
gives up."""

from __future__ import annotations

import math
from dataclasses import dataclass

from polynav.docking.shape import DockShape
from polynav.errors import ConfigError


@dataclass(frozen=True, slots=True)
class NavigatorConfig:
    """Timing and retry policy of the navigator [s, m].

    ``progress_reset_distance`` is the size of a "place" for counting failures: failures farther
    than this from the robot are forgotten. ``retry_min_time``: a place is given up only after
    this long. ``recovery_*``: the ladder's clearing radius, back-up distance and speed, turn
    and wait. ``replan_hysteresis``: a periodic re-plan's route replaces an unblocked current
    one only if shorter by this fraction of the remaining length, and by at least
    ``replan_min_gain`` [m], lengths counted as the time the controller takes over them: at
    full speed where the body has ``route_open_clearance`` [m] of room, slower below it, down to
    the speed of ``route_least_clearance`` (:func:`~polynav.nav.route_choice.drive_length`; the
    stack sets both from the controller's pace, 0 counts plain length). A route the lidar
    closes after it was planned open is re-planned at
    once, at most every ``closed_route_replan_period`` [s], rather than at the next period. A
    periodic re-plan plans the next ``replan_reach`` [m] of the
    route and keeps the rest; the whole way is planned again every ``full_replan_period``, and
    at every re-plan for ``people_detour_watch`` after people closed the route
    (:mod:`~polynav.nav.replanning`). A goal occupied by something not on the map (a robot
    standing there, a trolley) is waited for ``goal_wait`` [s], planning again every
    ``goal_wait_period`` (:mod:`~polynav.nav.goal_wait`); 0 fails it at once. At most
    ``passage_limit`` passages are closed per goal (:mod:`~polynav.nav.passages`), none later
    than ``passage_time_budget`` [s] after the first (a robot that has gone round that long
    without getting through is left to the retry budget, as any robot failing at a place); a
    block's place is looked for up to ``passage_look_ahead`` [m] along the route (at least the
    controller's stopping distance at speed), and a
    robot
    that cannot turn backs out along its way in by up to ``recovery_backout_distance`` [m]
    (:mod:`~polynav.nav.back_out`). A robot that may not reverse (``reverse_allowed`` false)
    neither backs out nor backs up. Docking finds the charger's plate in the scan near the
    marker and drives onto the pose seen (``dock_by_sight``; off: onto the marker's pose; the
    plate's shape ``dock_plate``, from the profile), and
    fails if the plate is not found, or a base with a beacon receiver does not see the
    charger's beacon, within ``dock_find_wait`` [s] at the approach
    (:mod:`~polynav.nav.charger_phases`).
    """

    replan_period: float = 3.0
    closed_route_replan_period: float = 0.5
    replan_min_remaining: float = 1.0
    blocked_wait: float = 1.5
    max_retries: int = 4
    progress_reset_distance: float = 1.0
    localization_grace: float = 5.0
    estop_fail_after: float | None = None
    undock_speed: float = 0.15
    undock_retry_after: float = 10.0
    undock_max_retries: int = 3
    dock_approach: float = 0.5
    dock_speed: float = 0.1
    dock_contact_wait: float = 3.0
    dock_timeout: float = 40.0
    dock_by_sight: bool = True
    dock_plate: DockShape = DockShape()
    dock_find_wait: float = 2.0
    retry_min_time: float = 30.0
    recovery_clear_radius: float = 1.5
    recovery_backup_distance: float = 0.3
    recovery_backup_speed: float = 0.15
    recovery_rotate_angle: float = math.pi / 2
    recovery_wait: float = 2.0
    replan_hysteresis: float = 0.15
    replan_min_gain: float = 0.3
    route_open_clearance: float = 0.0
    route_least_clearance: float = 0.0
    replan_reach: float = 10.0
    full_replan_period: float = 30.0
    people_detour_watch: float = 15.0
    goal_wait: float = 120.0
    goal_wait_period: float = 1.0
    passage_limit: int = 12
    passage_time_budget: float = 60.0
    passage_look_ahead: float = 2.5
    recovery_backout_distance: float = 3.0
    reverse_allowed: bool = True

    def __post_init__(self) -> None:
        for key in (
            "replan_period", "closed_route_replan_period", "blocked_wait", "localization_grace",
            "undock_speed",
            "undock_retry_after", "dock_approach", "dock_speed", "dock_contact_wait",
            "dock_timeout", "dock_find_wait", "recovery_clear_radius", "recovery_backup_distance",
            "recovery_backup_speed", "recovery_rotate_angle", "goal_wait_period",
            "recovery_backout_distance", "passage_look_ahead",
        ):
            if getattr(self, key) <= 0.0:
                raise ConfigError(f"nav.navigator.{key}", "must be > 0")
        if self.replan_min_remaining < 0.0:
            raise ConfigError("nav.navigator.replan_min_remaining", "must be >= 0")
        if self.progress_reset_distance <= 0.0:
            raise ConfigError("nav.navigator.progress_reset_distance", "must be > 0")
        for key in ("retry_min_time", "recovery_wait", "replan_min_gain", "replan_reach",
                    "full_replan_period", "people_detour_watch", "goal_wait",
                    "passage_time_budget", "route_open_clearance",
                    "route_least_clearance"):
            if getattr(self, key) < 0.0:
                raise ConfigError(f"nav.navigator.{key}", "must be >= 0")
        if not 0.0 <= self.replan_hysteresis < 1.0:
            raise ConfigError("nav.navigator.replan_hysteresis", "must be within [0, 1)")
        if self.max_retries < 0:
            raise ConfigError("nav.navigator.max_retries", "must be >= 0")
        if self.passage_limit < 0:
            raise ConfigError("nav.navigator.passage_limit", "must be >= 0")
        if self.undock_max_retries < 0:
            raise ConfigError("nav.navigator.undock_max_retries", "must be >= 0")
        if self.estop_fail_after is not None and self.estop_fail_after <= 0.0:
            raise ConfigError("nav.navigator.estop_fail_after", "must be > 0 or None")
