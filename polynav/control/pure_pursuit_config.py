"""The parameters of :class:`~polynav.control.pure_pursuit.RegulatedPurePursuit` and their
checks (SI units, Nav2 RPP names where they exist): a file of their own so the controller's
module holds the control law alone."""

from __future__ import annotations

import math
from dataclasses import dataclass

from polynav.errors import ConfigError, check_positive
from polynav.maps import costs

_KEY = "control.pure_pursuit."


@dataclass(frozen=True, slots=True)
class PurePursuitConfig:
    """Parameters of :class:`RegulatedPurePursuit`, SI units (Nav2 RPP names where they exist).

    Attributes:
        max_linear_velocity: top forward speed [m/s].
        max_angular_velocity: top turn rate [rad/s].
        linear_acceleration: forward speed-up limit [m/s²].
        linear_deceleration: slow-down limit [m/s²] (not applied to the stop when blocked).
        angular_acceleration: turn rate change limit [rad/s²].
        lookahead_time: the lookahead is the distance covered in this time [s] ...
        min_lookahead: ... but at least this [m] ...
        max_lookahead: ... and at most this [m].
        rotate_to_heading_min_angle: turn in place when the carrot is farther off the heading
            than this [rad].
        rotate_gain: turn-in-place rate per heading error [1/s] near the end of a turn.
        min_rotation_speed: slowest turn-in-place rate [rad/s] (static friction of real bases).
        regulated_min_radius: arcs tighter than this radius [m] slow the robot proportionally.
        min_regulated_speed: curvature and proximity regulation never go below this [m/s].
        proximity_cost_threshold: costs above this under or just ahead of the robot slow it.
        proximity_slowdown: fraction of the speed removed at the highest inflation cost.
        approach_velocity_scaling_dist: within this path distance [m] of the goal, slow down ...
        min_approach_velocity: ... but not below this [m/s], so the goal is reached.
        collision_lookahead_time: an obstacle closer than the distance covered in this time [s]
            (plus the braking distance) stops the robot.
        min_stop_distance: that stopping distance is never less than this [m].
        slowdown_distance: an obstacle on the path closer than this [m] slows the robot.
        xy_goal_tolerance: accepted final distance [m] to the goal.
        yaw_goal_tolerance: accepted final heading error [rad].
        goal_aim_fraction: the controller aims at this fraction of each goal tolerance.
        goal_settle_time: after this time [s] within a tolerance the full tolerance is accepted.
        path_search_distance: how far along the path [m] the robot's place and the carrot are
            searched from the last place.
        pose_filter_gain: weight of each new pose estimate against the odometry prediction
            (:mod:`polynav.control.pose_filter`); 1 steers by the raw estimate.
        pose_filter_reset_distance: an estimate this far [m] from the prediction is taken as is.
        standstill_speed: measured speeds [m/s] below this are odometry noise on a robot
            standing still: it coasts nowhere.
        clearance_time: the speed is at most the body's clearance along the arc ahead divided by
            this [s] (never below ``min_regulated_speed``): slow in tight gaps, fast in the open.
        sight_latency: the speed is at most one from which the robot, after this time [s] (a
            scan and a control period), brakes at ``linear_deceleration`` to a stop before its
            body reaches UNKNOWN space along the path (never below ``min_regulated_speed``):
            what is round a corner is seen only when the robot gets there.
    """

    max_linear_velocity: float = 0.6
    max_angular_velocity: float = 1.5
    linear_acceleration: float = 0.8
    linear_deceleration: float = 1.2
    angular_acceleration: float = 3.0
    lookahead_time: float = 1.5
    min_lookahead: float = 0.3
    max_lookahead: float = 0.9
    rotate_to_heading_min_angle: float = 0.785
    rotate_gain: float = 2.5
    min_rotation_speed: float = 0.1
    regulated_min_radius: float = 0.9
    min_regulated_speed: float = 0.1
    proximity_cost_threshold: int = 128
    proximity_slowdown: float = 0.5
    approach_velocity_scaling_dist: float = 0.6
    min_approach_velocity: float = 0.05
    collision_lookahead_time: float = 1.0
    min_stop_distance: float = 0.35
    slowdown_distance: float = 1.5
    xy_goal_tolerance: float = 0.05
    yaw_goal_tolerance: float = 0.05
    goal_aim_fraction: float = 0.3
    goal_settle_time: float = 1.0
    path_search_distance: float = 2.0
    pose_filter_gain: float = 0.2
    pose_filter_reset_distance: float = 0.2
    standstill_speed: float = 0.05
    clearance_time: float = 0.15
    sight_latency: float = 0.15

    def __post_init__(self) -> None:
        positive = (
            "max_linear_velocity", "max_angular_velocity", "linear_acceleration",
            "linear_deceleration", "angular_acceleration", "lookahead_time", "min_lookahead",
            "rotate_gain", "regulated_min_radius", "approach_velocity_scaling_dist",
            "min_approach_velocity", "collision_lookahead_time", "min_stop_distance",
            "xy_goal_tolerance", "yaw_goal_tolerance", "goal_settle_time", "standstill_speed",
            "clearance_time", "sight_latency",
        )
        check_positive(self, _KEY, positive)
        if self.max_lookahead < self.min_lookahead:
            raise ConfigError(_KEY + "max_lookahead", "must be >= min_lookahead")
        if not 0.0 < self.rotate_to_heading_min_angle <= math.pi:
            raise ConfigError(_KEY + "rotate_to_heading_min_angle", "must be within (0, pi]")
        if not 0.0 <= self.min_rotation_speed <= self.max_angular_velocity:
            raise ConfigError(_KEY + "min_rotation_speed", "must be within 0..max_angular_velocity")
        if not 0.0 <= self.min_regulated_speed <= self.max_linear_velocity:
            raise ConfigError(_KEY + "min_regulated_speed", "must be within 0..max_linear_velocity")
        if self.min_approach_velocity > self.max_linear_velocity:
            raise ConfigError(_KEY + "min_approach_velocity", "must be <= max_linear_velocity")
        if not 0 <= self.proximity_cost_threshold < costs.MAX_NON_OBSTACLE:
            raise ConfigError(
                _KEY + "proximity_cost_threshold", f"must be within 0..{costs.MAX_NON_OBSTACLE - 1}"
            )
        if not 0.0 <= self.proximity_slowdown < 1.0:
            raise ConfigError(_KEY + "proximity_slowdown", "must be within [0, 1)")
        if self.slowdown_distance < self.min_stop_distance:
            raise ConfigError(_KEY + "slowdown_distance", "must be >= min_stop_distance")
        if not 0.0 < self.goal_aim_fraction <= 1.0:
            raise ConfigError(_KEY + "goal_aim_fraction", "must be within (0, 1]")
        if self.xy_goal_tolerance >= self.min_lookahead:
            # Beyond min_lookahead from a reached goal the robot counts as moved away (pushed,
            # relocalized) and drives back; a tolerance that large would make that ambiguous.
            raise ConfigError(_KEY + "xy_goal_tolerance", "must be < min_lookahead")
        if not 0.0 < self.pose_filter_gain <= 1.0:
            raise ConfigError(_KEY + "pose_filter_gain", "must be within (0, 1]")
        if not self.pose_filter_reset_distance > 0.0:
            raise ConfigError(_KEY + "pose_filter_reset_distance", "must be > 0")
        if self.path_search_distance < self.max_lookahead:
            raise ConfigError(_KEY + "path_search_distance", "must be >= max_lookahead")
