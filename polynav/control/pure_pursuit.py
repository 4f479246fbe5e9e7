"""Regulated pure pursuit: follow a path by steering at a point a lookahead distance ahead.

After Macenski, Singh, Martin and Gines, "Regulated Pure Pursuit for Robot Path Tracking"
(Autonomous Robots, 2023), and the behaviour of Nav2's ``nav2_regulated_pure_pursuit_controller``:

- the lookahead grows with speed (``lookahead_time``), bounded by ``min/max_lookahead``;
- the linear speed is *regulated*: lowered on tight curvature, near obstacles (the costmap cost
  under the robot), when approaching the goal, and when an obstacle stands on the path ahead;
- the robot turns in place when the path leaves in a very different direction, and at the end
  turns in place to the goal heading;
- the path ahead is checked against the live costmap each period: an obstacle within stopping
  distance stops the robot (``BLOCKED``, the navigator re-plans), one farther ahead slows it.

Near the goal the carrot is the goal itself. A pure-pursuit arc through a fixed point is a circle
that passes exactly through it, so the approach converges on the point instead of orbiting it, and
the :class:`GoalChecker` latch then keeps the robot from creeping while it turns to the heading.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from polynav.control.goal_checker import GoalChecker, GoalCheckerConfig
from polynav.control.interface import ControlCommand, ControlStatus
from polynav.errors import ConfigError
from polynav.geometry import Pose2D, Twist, angle_diff
from polynav.maps import costs
from polynav.maps.interface import CostGrid
from polynav.planning.path import Path

_AIM_FRACTION = 0.4
"""The controller aims this fraction of the xy tolerance, keeping the rest for estimate noise."""


@dataclass(frozen=True, slots=True)
class PurePursuitConfig:
    """Limits [m/s, rad/s, m/s², rad/s²], lookahead [s, m], regulation and goal tolerances."""

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
    proximity_slowdown: float = 0.5
    approach_velocity_scaling_dist: float = 0.6
    min_approach_velocity: float = 0.05
    collision_lookahead_time: float = 1.0
    min_stop_distance: float = 0.35
    slowdown_distance: float = 1.5
    xy_goal_tolerance: float = 0.05
    yaw_goal_tolerance: float = 0.05

    def __post_init__(self) -> None:
        positive = (
            "max_linear_velocity", "max_angular_velocity", "linear_acceleration",
            "linear_deceleration", "angular_acceleration", "lookahead_time", "min_lookahead",
            "rotate_to_heading_min_angle", "rotate_gain", "regulated_min_radius",
            "approach_velocity_scaling_dist", "min_approach_velocity", "collision_lookahead_time",
            "min_stop_distance", "xy_goal_tolerance", "yaw_goal_tolerance",
        )
        for key in positive:
            if getattr(self, key) <= 0.0:
                raise ConfigError(f"control.pure_pursuit.{key}", "must be > 0")
        if self.max_lookahead < self.min_lookahead:
            raise ConfigError("control.pure_pursuit.max_lookahead", "must be >= min_lookahead")
        if not 0.0 <= self.min_regulated_speed <= self.max_linear_velocity:
            raise ConfigError(
                "control.pure_pursuit.min_regulated_speed", "must be within 0..max_linear_velocity"
            )
        if self.min_approach_velocity > self.max_linear_velocity:
            raise ConfigError(
                "control.pure_pursuit.min_approach_velocity", "must be <= max_linear_velocity"
            )
        if not 0.0 <= self.proximity_slowdown < 1.0:
            raise ConfigError("control.pure_pursuit.proximity_slowdown", "must be within [0, 1)")
        if self.slowdown_distance < self.min_stop_distance:
            raise ConfigError(
                "control.pure_pursuit.slowdown_distance", "must be >= min_stop_distance"
            )
        if not 0.0 <= self.min_rotation_speed <= self.max_angular_velocity:
            raise ConfigError(
                "control.pure_pursuit.min_rotation_speed", "must be within 0..max_angular_velocity"
            )


class RegulatedPurePursuit:
    """The path-following controller (implements ``polynav.control.interface.Controller``)."""

    def __init__(self, config: PurePursuitConfig | None = None) -> None:
        self.config = config or PurePursuitConfig()
        self._goal_checker = GoalChecker(
            GoalCheckerConfig(
                self.config.xy_goal_tolerance * _AIM_FRACTION, self.config.yaw_goal_tolerance
            )
        )
        self._points: npt.NDArray[np.float64] = np.zeros((0, 2))
        self._cumulative: npt.NDArray[np.float64] = np.zeros(0)
        self._goal: Pose2D | None = None
        self._closest = 0

    # -- Controller protocol -----------------------------------------------------------------

    def set_path(self, path: Path, goal: Pose2D) -> None:
        points = np.asarray(path.points, dtype=np.float64).reshape(-1, 2)
        if points.shape[0] == 0 or not np.allclose(points[-1], (goal.x, goal.y)):
            points = np.vstack([points, [goal.x, goal.y]])
        self._points = points
        seg = np.hypot(*np.diff(points, axis=0).T) if points.shape[0] > 1 else np.zeros(0)
        self._cumulative = np.concatenate(([0.0], np.cumsum(seg)))
        if self._goal is None or goal != self._goal:
            self._goal_checker.reset()
        self._goal = goal
        self._closest = 0

    def reset(self) -> None:
        self._points = np.zeros((0, 2))
        self._cumulative = np.zeros(0)
        self._goal = None
        self._closest = 0
        self._goal_checker.reset()

    def compute(
        self, pose: Pose2D, velocity: Twist, costmap: CostGrid, dt: float
    ) -> ControlCommand:
        cfg = self.config
        if self._goal is None:
            return ControlCommand(Twist(), ControlStatus.BLOCKED)
        goal = self._goal
        if not self._goal_checker.xy_reached:
            # Aim well inside the tolerance; accept the tolerance itself only once the goal is
            # abeam or behind, where driving on would only take the robot away from it.
            gx, gy = goal.x - pose.x, goal.y - pose.y
            ahead = gx * math.cos(pose.theta) + gy * math.sin(pose.theta)
            if math.hypot(gx, gy) <= cfg.xy_goal_tolerance and ahead <= 0.0:
                self._goal_checker.latch()
        if self._goal_checker.position_reached(pose, goal):
            error = angle_diff(goal.theta, pose.theta)
            if abs(error) <= cfg.yaw_goal_tolerance:
                return ControlCommand(Twist(), ControlStatus.ARRIVED)
            return ControlCommand(self._rotate(error, velocity, dt), ControlStatus.ROTATING)

        self._advance_closest(pose)
        remaining = self._remaining(pose)
        lookahead = min(max(abs(velocity.linear) * cfg.lookahead_time, cfg.min_lookahead),
                        cfg.max_lookahead)
        cx, cy = self._carrot(pose, lookahead, remaining)
        # The carrot in the robot frame.
        dx, dy = cx - pose.x, cy - pose.y
        c, s = math.cos(pose.theta), math.sin(pose.theta)
        fx, fy = c * dx + s * dy, -s * dx + c * dy
        bearing = math.atan2(fy, fx)
        if abs(bearing) > cfg.rotate_to_heading_min_angle:
            return ControlCommand(self._rotate(bearing, velocity, dt), ControlStatus.ROTATING)

        d2 = fx * fx + fy * fy
        curvature = 2.0 * fy / d2 if d2 > 1e-12 else 0.0
        speed = self._regulated_speed(pose, curvature, costmap, remaining)
        blocked_at = self._distance_to_blocked(pose, costmap, cfg.slowdown_distance)
        status = ControlStatus.TRACKING
        if blocked_at is not None:
            braking = velocity.linear**2 / (2.0 * cfg.linear_deceleration)
            stop_distance = max(cfg.min_stop_distance,
                                braking + abs(velocity.linear) * cfg.collision_lookahead_time)
            if blocked_at <= stop_distance:
                return ControlCommand(Twist(), ControlStatus.BLOCKED)
            span = max(cfg.slowdown_distance - stop_distance, 1e-6)
            fraction = min(1.0, (blocked_at - stop_distance) / span)
            speed = min(speed, max(cfg.min_regulated_speed, cfg.max_linear_velocity * fraction))
            status = ControlStatus.SLOWING

        linear = _limit(speed, velocity.linear, cfg.linear_acceleration,
                        cfg.linear_deceleration, dt)
        angular = linear * curvature
        if abs(angular) > cfg.max_angular_velocity:
            # Keep the arc: slow down rather than cut the corner.
            angular = math.copysign(cfg.max_angular_velocity, angular)
            linear = abs(angular / curvature)
        return ControlCommand(Twist(linear, angular), status)

    # -- parts -------------------------------------------------------------------------------

    def _rotate(self, error: float, velocity: Twist, dt: float) -> Twist:
        """Turn in place toward ``error`` [rad], slowing so it stops on the heading."""
        cfg = self.config
        magnitude = min(
            cfg.max_angular_velocity,
            math.sqrt(2.0 * cfg.angular_acceleration * abs(error)),
            cfg.rotate_gain * abs(error),
        )
        target = math.copysign(max(magnitude, cfg.min_rotation_speed), error)
        step = cfg.angular_acceleration * dt if dt > 0.0 else math.inf
        angular = min(max(target, velocity.angular - step), velocity.angular + step)
        if angular * error < 0.0:
            # Still turning the wrong way from the last command: brake, never accelerate away.
            angular = 0.0 if abs(velocity.angular) <= step else angular
        return Twist(0.0, angular)

    def _advance_closest(self, pose: Pose2D) -> None:
        """Move the nearest-point index forward; the search only looks ahead (PythonRobotics)."""
        pts = self._points
        stop = int(np.searchsorted(self._cumulative, self._cumulative[self._closest] + 2.0)) + 1
        window = pts[self._closest : max(stop, self._closest + 2)]
        d = np.hypot(window[:, 0] - pose.x, window[:, 1] - pose.y)
        best = int(np.argmin(d))
        if d[best] > 0.5:
            # Far from the window (a relocalization jump): search the whole rest of the path.
            rest = pts[self._closest :]
            best = int(np.argmin(np.hypot(rest[:, 0] - pose.x, rest[:, 1] - pose.y)))
        self._closest += best

    def _remaining(self, pose: Pose2D) -> float:
        p = self._points[self._closest]
        return float(self._cumulative[-1] - self._cumulative[self._closest]
                     + math.hypot(p[0] - pose.x, p[1] - pose.y))

    def _carrot(self, pose: Pose2D, lookahead: float, remaining: float) -> tuple[float, float]:
        goal = self._goal
        assert goal is not None
        if math.hypot(goal.x - pose.x, goal.y - pose.y) <= lookahead or remaining <= lookahead:
            return (goal.x, goal.y)
        pts = self._points
        for j in range(self._closest + 1, pts.shape[0]):
            if math.hypot(pts[j, 0] - pose.x, pts[j, 1] - pose.y) >= lookahead:
                return _circle_crossing(pts[j - 1], pts[j], pose, lookahead)
        return (goal.x, goal.y)

    def _regulated_speed(
        self, pose: Pose2D, curvature: float, costmap: CostGrid, remaining: float
    ) -> float:
        cfg = self.config
        speed = cfg.max_linear_velocity
        if abs(curvature) > 1e-9:
            radius = 1.0 / abs(curvature)
            if radius < cfg.regulated_min_radius:
                speed *= radius / cfg.regulated_min_radius
        cost = _cost_at(costmap, pose.x, pose.y)
        if 0 < cost < costs.INSCRIBED:
            speed *= 1.0 - cfg.proximity_slowdown * cost / costs.MAX_NON_OBSTACLE
        speed = max(speed, cfg.min_regulated_speed)
        if remaining < cfg.approach_velocity_scaling_dist:
            approach = cfg.max_linear_velocity * remaining / cfg.approach_velocity_scaling_dist
            speed = min(speed, max(approach, cfg.min_approach_velocity))
        return speed

    def _distance_to_blocked(
        self, pose: Pose2D, costmap: CostGrid, horizon: float
    ) -> float | None:
        """Path distance [m] from the robot to the first cell ahead its footprint would hit."""
        start = self._closest
        stop = int(np.searchsorted(self._cumulative, self._cumulative[start] + horizon)) + 1
        pts = self._points[start:stop]
        if pts.shape[0] == 0:
            return None
        info = costmap.info
        cells = info.world_to_cells(pts)
        ix, iy = cells[:, 0], cells[:, 1]
        inside = (ix >= 0) & (iy >= 0) & (ix < info.width) & (iy < info.height)
        values = np.full(pts.shape[0], costs.LETHAL, dtype=np.int64)
        values[inside] = costmap.costs[iy[inside], ix[inside]]
        blocked = (values >= costs.INSCRIBED) & (values != costs.UNKNOWN)
        if blocked[0]:
            # The robot starts in an inscribed cell (pushed against a wall, or a plan that
            # escapes one): only a blocked cell after the first clear one counts.
            clear = np.flatnonzero(~blocked)
            if clear.size == 0:
                return None
            blocked[: clear[0]] = False
        hits = np.flatnonzero(blocked)
        if hits.size == 0:
            return None
        k = int(hits[0])
        p = pts[0]
        return float(self._cumulative[start + k] - self._cumulative[start]
                     + math.hypot(p[0] - pose.x, p[1] - pose.y))


def _limit(target: float, current: float, accel: float, decel: float, dt: float) -> float:
    """``target`` within what the base can reach from ``current`` in ``dt`` (forward motion)."""
    if dt <= 0.0:
        return target
    if target >= current:
        return min(target, current + accel * dt)
    return max(target, current - decel * dt)


def _cost_at(costmap: CostGrid, x: float, y: float) -> int:
    ix, iy = costmap.info.world_to_cell(x, y)
    if not costmap.info.contains(ix, iy):
        return costs.LETHAL
    return int(costmap.costs[iy, ix])


def _circle_crossing(
    a: npt.NDArray[np.float64], b: npt.NDArray[np.float64], pose: Pose2D, radius: float
) -> tuple[float, float]:
    """Where segment a→b leaves the circle of ``radius`` around the robot (a inside, b outside)."""
    ax, ay = a[0] - pose.x, a[1] - pose.y
    bx, by = b[0] - pose.x, b[1] - pose.y
    dx, dy = bx - ax, by - ay
    qa = dx * dx + dy * dy
    if qa < 1e-12:
        return (float(b[0]), float(b[1]))
    qb = 2.0 * (ax * dx + ay * dy)
    qc = ax * ax + ay * ay - radius * radius
    disc = max(qb * qb - 4.0 * qa * qc, 0.0)
    t = min(max((-qb + math.sqrt(disc)) / (2.0 * qa), 0.0), 1.0)
    return (float(a[0] + t * dx), float(a[1] + t * dy))
