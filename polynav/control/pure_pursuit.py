"""Regulated pure pursuit: follow a path by steering on the arc through a point ahead on it.

After Macenski, Singh, Martin and Gines, "Regulated Pure Pursuit for Robot Path Tracking"
(Autonomous Robots, 2023), and the behaviour of Nav2's ``nav2_regulated_pure_pursuit_controller``.
Each control period :meth:`RegulatedPurePursuit.compute` goes through these steps:

1. **Goal.** Once the robot stands on the goal position it stops translating and turns in place
   to the goal heading (``ROTATING``), then reports ``ARRIVED``. The position is *latched* (see
   :mod:`polynav.control.goal_checker`): estimate jitter while turning never restarts driving.
2. **Place and carrot.** The robot's place on the path is searched forward from the last one
   (:mod:`polynav.control.tracked_path`); the carrot is where the path leaves the lookahead circle,
   the lookahead growing with speed. When the rest of the path lies inside the circle the carrot
   is the goal itself.
3. **Turn in place** (``ROTATING``) while the carrot is more than ``rotate_to_heading_min_angle``
   off the heading: at the start when the path leaves sideways or backwards, and mid-path at a
   hairpin. The turn ends once aligned and slowed down, so driving starts on a straight arc.
4. **Track**: curvature 2y/L² to the carrot; the linear speed is *regulated* by curvature, by the
   cost under and just ahead of the robot, and by the distance left to the goal
   (:mod:`polynav.control.regulation`); the turn rate is speed × curvature.
5. **Collision check**: the robot's footprint (circle or polygon, :mod:`polynav.footprint`) is
   placed along the path ahead and along the arc about to be driven and tested against LETHAL
   cells (:mod:`polynav.control.collision`). An obstacle within the stopping distance (what the
   robot covers in ``collision_lookahead_time`` plus its braking distance) stops the robot
   (``BLOCKED``: the navigator recovers and re-plans); one within ``slowdown_distance`` slows it
   (``SLOWING``). Where the path is clear but the arc to the carrot is not (a body that fits a
   gap only lined up with the path, the arc cutting the corner into it), the robot *closes in*
   on the path first: a nearer carrot, at the slowest regulated speed, or a turn in place onto
   the path's heading; only when neither is clear is it ``BLOCKED``. The body's *clearance*
   along the arc caps the speed too (``clearance_time``): in a gap barely wider than the robot
   it creeps through rather than stopping, and where the clearance allows it drives at the full
   ``max_linear_velocity``.
   A turn in place is checked by sweeping the footprint through the turn (a polygon's corners
   swing out; a circle never changes), and turns the long way round when only that way is clear.
   Odometry of a robot standing still reports a few mm/s of noise: below ``standstill_speed``
   the robot is not coasting anywhere, so no coasting arc (of a tiny radius that would touch
   every post nearby) is checked.
6. **Limits**: never above the velocity limits, and within the acceleration limits from the
   *measured* velocity, except the stop when ``BLOCKED``, which is immediate.

Precision at the goal. The acceptance tests measure the true pose to 0.1 m / 0.1 rad while the
controller sees a localization estimate a few centimetres off, so the controller does not spend
its tolerances on itself: it *aims* at ``goal_aim_fraction`` of each tolerance and keeps the rest
for the estimate's error. It accepts the full tolerance only when aiming closer would mean driving
on past the goal (the goal is abeam or behind), turning back past the heading (it overshot), or
has not succeeded within ``goal_settle_time`` (a base that cannot creep that slowly). Steering at
the goal itself converges instead of orbiting: the pure pursuit arc through a fixed point passes
exactly through it, and where the turn rate cannot follow the arc the speed drops so that it can.
A goal close by but far off to the side is a large bearing, so the robot turns toward it first.
"""

from __future__ import annotations

import logging
import math

import numpy as np
import numpy.typing as npt

from polynav import footprint as body
from polynav.control import collision, path_kernels, regulation
from polynav.control.goal_checker import GoalChecker
from polynav.control.interface import ControlCommand, ControlStatus
from polynav.control.pose_filter import PoseFilter
from polynav.control.pure_pursuit_config import PurePursuitConfig
from polynav.control.tracked_path import TrackedPath
from polynav.footprint import Footprint
from polynav.geometry import Pose2D, Twist, angle_diff, wrap_angle
from polynav.maps import costs
from polynav.maps.interface import CostGrid
from polynav.planning.path import Path

__all__ = ["DEFAULT_FOOTPRINT", "PurePursuitConfig", "RegulatedPurePursuit"]

log = logging.getLogger(__name__)

_CLOSE_IN_SHARES = (0.5, 0.25)  # nearer carrots, as shares of the lookahead, tried in turn
_CLOSE_IN_ALIGNED = 0.05  # [rad] lined up with the path closely enough to need no turn
_CREEP_MARGIN = 0.02  # [m/s] over the slowest regulated speed, a robot still creeps

DEFAULT_FOOTPRINT = Footprint.circle(0.25)
"""The demo robot's body, when none is given."""


class RegulatedPurePursuit:
    """The path-following controller; implements :class:`polynav.control.interface.Controller`.

    Args:
        config: the tuning.
        footprint: the robot's body, for every collision check; a 0.25 m disk if not given.
    """

    def __init__(
        self, config: PurePursuitConfig | None = None, *, footprint: Footprint | None = None
    ) -> None:
        path_kernels.warm_up()
        self.config = config or PurePursuitConfig()
        self.footprint = footprint or DEFAULT_FOOTPRINT
        self._goal_checker = GoalChecker(
            self.config.xy_goal_tolerance, self.config.yaw_goal_tolerance
        )
        self._filter = PoseFilter(
            self.config.pose_filter_gain, self.config.pose_filter_reset_distance
        )
        self._path: TrackedPath | None = None
        self._goal: Pose2D | None = None
        self._place = 0.0  # the robot's arc length along the path [m]
        self._rotating = False  # in a turn in place toward the carrot
        self._arrived = False
        self._settle = 0.0  # time [s] spent within a goal tolerance without reaching the aim
        self._status: ControlStatus | None = None
        self._reverse_allowed = False

    def set_goal_options(self, *, yaw_tolerance: float | None, reverse_allowed: bool) -> None:
        """The next goals' heading tolerance [rad] (``None``: the configured one), and whether
        the goal heading reversed is accepted too (a robot that may stop tail-first)."""
        self._goal_checker.yaw_tolerance = (
            self.config.yaw_goal_tolerance if yaw_tolerance is None else yaw_tolerance
        )
        self._reverse_allowed = reverse_allowed

    # -- Controller protocol -----------------------------------------------------------------

    def set_path(self, path: Path, goal: Pose2D) -> None:
        """Follow ``path`` to ``goal``; the same goal again (a re-plan) keeps the goal latch."""
        points = np.asarray(path.points, dtype=np.float64).reshape(-1, 2)
        if points.shape[0] == 0 or math.hypot(*(points[-1] - (goal.x, goal.y))) > 1e-6:
            # A grid planner ends on the goal cell's centre; the robot must end on the goal.
            points = np.vstack([points, [goal.x, goal.y]])
        self._path = TrackedPath.from_points(points)
        self._place = 0.0
        if goal != self._goal:
            self._goal_checker.reset()
            self._arrived = False
            self._settle = 0.0
            self._rotating = False
        self._goal = goal

    def reset(self) -> None:
        """Forget the path, the goal latch and the smoothed pose (a cancel, a recovery)."""
        self._path = None
        self._goal = None
        self._place = 0.0
        self._rotating = False
        self._arrived = False
        self._settle = 0.0
        self._status = None
        self._goal_checker.reset()
        self._filter.reset()

    def compute(
        self, pose: Pose2D, velocity: Twist, costmap: CostGrid, dt: float
    ) -> ControlCommand:
        """The velocity for the next ``dt`` [s] from the estimated ``pose`` and measured velocity.

        ``dt`` is also taken as the time since the last call, over which ``velocity`` moved the
        robot (the pose filter's prediction). Without a path (never set, or after :meth:`reset`)
        the answer is a stop, ``BLOCKED``.
        """
        pose = self._filter.update(pose, velocity, dt)
        if self._path is None or self._goal is None:
            return self._answer(Twist(), ControlStatus.BLOCKED)
        goal = self._goal
        distance = pose.distance_to(goal)
        checker = self._goal_checker
        if checker.xy_reached and distance > self.config.min_lookahead:
            log.info("%.2f m from the goal after reaching it (moved?): driving back", distance)
            checker.reset()
            self._arrived = False
            self._settle = 0.0
        if self._arrived:
            return self._answer(Twist(), ControlStatus.ARRIVED)
        if not checker.xy_reached and self._position_done(pose, goal, distance, dt):
            checker.latch()
            self._settle = 0.0
        if checker.xy_reached:
            return self._turn_to_goal(pose, velocity, costmap, dt)
        return self._track(pose, velocity, costmap, dt)

    # -- goal --------------------------------------------------------------------------------

    def _position_done(self, pose: Pose2D, goal: Pose2D, distance: float, dt: float) -> bool:
        """Stop translating? At the aim, or within tolerance where getting closer is not on."""
        cfg = self.config
        if distance <= cfg.xy_goal_tolerance * cfg.goal_aim_fraction:
            return True
        if distance > cfg.xy_goal_tolerance:
            self._settle = 0.0
            return False
        ahead = (goal.x - pose.x) * math.cos(pose.theta) + (goal.y - pose.y) * math.sin(pose.theta)
        if ahead <= 0.0:
            # Abeam or behind: driving on can only take the robot away from the goal.
            return True
        self._settle += dt
        return self._settle >= cfg.goal_settle_time

    def _turn_to_goal(
        self, pose: Pose2D, velocity: Twist, costmap: CostGrid, dt: float
    ) -> ControlCommand:
        cfg = self.config
        goal = self._goal
        assert goal is not None
        error = angle_diff(goal.theta, pose.theta)
        if self._reverse_allowed:
            reversed_error = angle_diff(goal.theta + math.pi, pose.theta)
            if abs(reversed_error) < abs(error):
                goal = Pose2D(goal.x, goal.y, wrap_angle(goal.theta + math.pi))
                error = reversed_error
        if self._goal_checker.heading_reached(pose, goal):
            self._settle += dt
            overshot = error * velocity.angular < 0.0
            if (
                abs(error) <= self._goal_checker.yaw_tolerance * cfg.goal_aim_fraction
                or overshot
                or self._settle >= cfg.goal_settle_time
            ):
                self._arrived = True
                log.debug("arrived: %.3f m and %.3f rad from the goal", pose.distance_to(goal),
                          error)
                return self._answer(Twist(), ControlStatus.ARRIVED)
        else:
            self._settle = 0.0
        return self._rotate(pose, error, velocity, costmap, dt)

    def _rotate(
        self, pose: Pose2D, error: float, velocity: Twist, costmap: CostGrid, dt: float
    ) -> ControlCommand:
        """Turn in place by ``error`` [rad], the long way round if only that way is clear."""
        if velocity.linear > self.config.standstill_speed and self._coasting_collides(
            pose, velocity, costmap
        ):
            return self._answer(Twist(), ControlStatus.BLOCKED)
        if collision.turn_collides(self.footprint, costmap, pose, error):
            other = error - math.copysign(2.0 * math.pi, error)
            if collision.turn_collides(self.footprint, costmap, pose, other):
                log.debug("no way to turn %.2f rad in place: blocked", error)
                return self._answer(Twist(), ControlStatus.BLOCKED)
            error = other
        return self._answer(self._turn(error, velocity, dt), ControlStatus.ROTATING)

    def _turn(self, error: float, velocity: Twist, dt: float) -> Twist:
        """Turn in place toward a heading ``error`` [rad] away, braking any forward motion."""
        cfg = self.config
        target = regulation.rotation_speed(
            error,
            max_speed=cfg.max_angular_velocity,
            acceleration=cfg.angular_acceleration,
            gain=cfg.rotate_gain,
            min_speed=cfg.min_rotation_speed,
        )
        angular = regulation.limit_angular(
            target, velocity.angular, acceleration=cfg.angular_acceleration, dt=dt
        )
        linear = regulation.limit_linear(
            0.0,
            velocity.linear,
            acceleration=cfg.linear_acceleration,
            deceleration=cfg.linear_deceleration,
            dt=dt,
        )
        return Twist(linear, angular)

    # -- tracking ----------------------------------------------------------------------------

    def _track(
        self, pose: Pose2D, velocity: Twist, costmap: CostGrid, dt: float
    ) -> ControlCommand:
        cfg = self.config
        path, goal = self._path, self._goal
        assert path is not None and goal is not None
        self._place = path.project(
            pose.x,
            pose.y,
            start=self._place,
            window=cfg.path_search_distance,
            heading=pose.theta,
        )
        lookahead = regulation.lookahead_distance(
            velocity.linear,
            lookahead_time=cfg.lookahead_time,
            min_lookahead=cfg.min_lookahead,
            max_lookahead=cfg.max_lookahead,
        )
        carrot = path.lookahead(
            pose.x, pose.y, start=self._place, radius=lookahead, window=cfg.path_search_distance
        )
        at_goal = carrot is None
        cx, cy = (goal.x, goal.y) if carrot is None else carrot
        c, s = math.cos(pose.theta), math.sin(pose.theta)
        fx = c * (cx - pose.x) + s * (cy - pose.y)
        fy = -s * (cx - pose.x) + c * (cy - pose.y)
        bearing = math.atan2(fy, fx)

        if self._rotating:
            # Leave the turn only once aligned, where its rate has come down to what one period
            # of angular acceleration can take away: tracking then starts on a nearly straight
            # arc, and the bearing cannot hover about the entry angle, flipping in and out.
            settled = max(cfg.angular_acceleration * dt, cfg.min_rotation_speed)
            if abs(bearing) <= settled / cfg.rotate_gain and abs(velocity.angular) <= settled:
                self._rotating = False
        elif abs(bearing) > cfg.rotate_to_heading_min_angle:
            self._rotating = True
        if self._rotating:
            return self._rotate(pose, bearing, velocity, costmap, dt)

        if at_goal:
            # Steer to pass within half the aim, not through the goal's centre: a straight line
            # already doing so needs no turn (its closest approach is inside the aim, at a
            # bearing under 30 degrees), and steering by the last centimetres of a noisy lateral
            # offset (curvature grows as 1/distance²) would only make the robot wriggle.
            band = 0.5 * cfg.xy_goal_tolerance * cfg.goal_aim_fraction
            lateral = math.copysign(max(abs(fy) - band, 0.0), fy)
            kappa = 2.0 * lateral / max(fx * fx + fy * fy, 1e-12)
        else:
            kappa = regulation.curvature(fx, fy)
        # Near the goal the straight-line distance is the one that matters (the robot may be a
        # little off the path's last segment); before that, the distance along the path.
        remaining = pose.distance_to(goal) if at_goal else path.length - self._place
        stop_at = regulation.stop_distance(
            velocity.linear,
            deceleration=cfg.linear_deceleration,
            lookahead_time=cfg.collision_lookahead_time,
            minimum=cfg.min_stop_distance,
        )
        step = 0.5 * costmap.info.resolution
        horizon = max(cfg.slowdown_distance, stop_at)
        arc_s = np.arange(self._place, min(path.length, self._place + horizon) + step, step)
        arc_s = np.minimum(arc_s, path.length)
        ahead_poses = path.poses_at(arc_s)
        ahead = collision.costs_at(costmap, ahead_poses[:, :2])

        speed = regulation.curvature_speed(
            cfg.max_linear_velocity, kappa, min_radius=cfg.regulated_min_radius
        )
        preview = velocity.linear**2 / (2.0 * cfg.linear_deceleration) + step
        near = ahead[arc_s - self._place <= preview]
        cost = max(collision.cost_at(costmap, pose.x, pose.y),
                   int(near[near != costs.UNKNOWN].max(initial=0)))
        factor = regulation.proximity_factor(
            cost, cost_threshold=cfg.proximity_cost_threshold, slowdown=cfg.proximity_slowdown
        )
        slowing = factor < 1.0
        speed = max(speed * factor, cfg.min_regulated_speed)
        speed = regulation.approach_speed(
            speed,
            remaining,
            scaling_distance=cfg.approach_velocity_scaling_dist,
            min_speed=cfg.min_approach_velocity,
            deceleration=cfg.linear_deceleration,
        )

        hit = collision.first_footprint_collision(self.footprint, costmap, ahead_poses)
        if hit is not None:
            obstacle = float(arc_s[hit]) - self._place
            if obstacle <= stop_at:
                log.debug("obstacle on the path %.2f m ahead: blocked", obstacle)
                return self._answer(Twist(), ControlStatus.BLOCKED)
            capped = regulation.obstacle_speed(
                obstacle,
                stop_at=stop_at,
                slowdown_distance=cfg.slowdown_distance,
                max_speed=cfg.max_linear_velocity,
                min_speed=cfg.min_regulated_speed,
            )
            if capped < speed:
                speed, slowing = capped, True
        seen = self._seen_speed(ahead_poses, arc_s, costmap)
        if seen < speed:
            speed, slowing = seen, True
        arc = self._arc_to_carrot(pose, kappa, math.hypot(fx, fy), stop_at, costmap)
        if collision.first_footprint_collision(self.footprint, costmap, arc) is not None:
            # The path is clear (checked above) but the shortcut to the carrot is not: a body
            # that only fits a gap lined up with the path. Get back onto the path instead.
            closer = self._close_in(pose, velocity, costmap, dt, lookahead, stop_at)
            if closer is not None:
                return closer
            log.debug("the arc to the carrot runs into an obstacle: blocked")
            return self._answer(Twist(), ControlStatus.BLOCKED)
        room = self._clearance_speed(arc, costmap)
        if room < speed:
            speed, slowing = room, True

        twist = self._limit(speed, kappa, velocity, dt)
        return self._answer(twist, ControlStatus.SLOWING if slowing else ControlStatus.TRACKING)

    def _close_in(
        self,
        pose: Pose2D,
        velocity: Twist,
        costmap: CostGrid,
        dt: float,
        lookahead: float,
        stop_at: float,
    ) -> ControlCommand | None:
        """Follow the path more closely where the arc to the carrot cuts into an obstacle: a
        nearer carrot (a tighter arc back onto the path) at the slowest regulated speed; else,
        lined up with the path, straight on along it to the corner the arc cut; else a turn in
        place onto the path's heading (from a creep at most); ``None`` when none is clear.

        Pure pursuit cuts corners by design; in a field of posts a rectangular body that fits
        a gap only when lined up with it must not, or it stops at every gap."""
        cfg = self.config
        path = self._path
        assert path is not None
        for share in _CLOSE_IN_SHARES:
            carrot = path.lookahead(pose.x, pose.y, start=self._place, radius=share * lookahead,
                                    window=cfg.path_search_distance)
            if carrot is None:
                break
            c, s = math.cos(pose.theta), math.sin(pose.theta)
            fx = c * (carrot[0] - pose.x) + s * (carrot[1] - pose.y)
            fy = -s * (carrot[0] - pose.x) + c * (carrot[1] - pose.y)
            if fx <= 0.0 or abs(math.atan2(fy, fx)) > cfg.rotate_to_heading_min_angle:
                continue
            kappa = regulation.curvature(fx, fy)
            arc = self._arc_to_carrot(pose, kappa, math.hypot(fx, fy), stop_at, costmap)
            if collision.first_footprint_collision(self.footprint, costmap, arc) is None:
                speed = min(cfg.min_regulated_speed, self._clearance_speed(arc, costmap))
                return self._answer(self._limit(speed, kappa, velocity, dt),
                                    ControlStatus.SLOWING)
        heading = float(path.headings_at(np.array([self._place]))[0])
        error = angle_diff(heading, pose.theta)
        if abs(error) < _CLOSE_IN_ALIGNED:
            # Lined up with the path (to a corner the arc would cut): straight on along it,
            # slowly, as long as straight ahead is clear; past the corner the robot turns.
            ahead = collision.arc_poses(pose, 0.0, stop_at, 0.5 * costmap.info.resolution)
            if collision.first_footprint_collision(self.footprint, costmap, ahead) is not None:
                return None
            speed = min(cfg.min_regulated_speed, self._clearance_speed(ahead, costmap))
            return self._answer(self._limit(speed, 0.0, velocity, dt), ControlStatus.SLOWING)
        if velocity.linear > cfg.min_regulated_speed + _CREEP_MARGIN:
            return None
        if collision.turn_collides(self.footprint, costmap, pose, error):
            return None
        # Creeping at most: the turn's own check covers what it rolls on while it stops.
        answer = self._rotate(pose, error, velocity, costmap, dt)
        return None if answer.status is ControlStatus.BLOCKED else answer

    def _arc_to_carrot(
        self, pose: Pose2D, kappa: float, chord: float, stop_at: float, costmap: CostGrid
    ) -> npt.NDArray[np.float64]:
        """Poses (N, 3) along the arc about to be driven, up to the stopping distance.

        The path check alone misses a robot cutting a corner into a wall. The arc is checked only
        up to the carrot, ``chord`` [m] away, where it meets the path again: beyond it the robot
        would follow the path, not the arc, and the path check covers that stretch.
        """
        half = min(abs(kappa) * chord / 2.0, 1.0)
        to_carrot = chord if abs(kappa) < 1e-9 else 2.0 * math.asin(half) / abs(kappa)
        length = max(min(stop_at, to_carrot), 0.0)
        return collision.arc_poses(pose, kappa, length, 0.5 * costmap.info.resolution)

    def _clearance_speed(self, arc: npt.NDArray[np.float64], costmap: CostGrid) -> float:
        """The fastest speed [m/s] the body's clearance along ``arc`` allows.

        Clearance over time: at ``clearance_time`` from touching, whatever the speed. A robot
        squeezing through a gap one cell wider than itself creeps; in the open it is uncapped.
        """
        cfg = self.config
        horizon = cfg.max_linear_velocity * cfg.clearance_time
        gaps = body.clearances(self.footprint, costmap, arc, horizon=horizon)
        gap = float(gaps.min(initial=horizon))
        return max(gap / cfg.clearance_time, cfg.min_regulated_speed)

    def _seen_speed(
        self, poses: npt.NDArray[np.float64], arc_s: npt.NDArray[np.float64], costmap: CostGrid
    ) -> float:
        """The fastest speed [m/s] from which the robot stops before its body, along the path
        ``poses`` (at arc lengths ``arc_s``), first reaches space the sensors have not seen.

        Without a map the costmap's UNKNOWN cells are where a wall round a corner may stand:
        driving no faster than the seen floor allows, the robot meets what appears there with
        room to stop, whatever the clearance pace (``clearance_time``). With a map the route
        stays on known floor and this never binds. The cells the body already overlaps do
        not count (it stands there), nor does anything beyond ``poses``.
        """
        cfg = self.config
        first = body.first_collision(self.footprint, costmap, poses, unknown_is_lethal=True,
                                     ignore_start=True)
        if first is None:
            return math.inf
        room = float(arc_s[first]) - self._place
        speed = regulation.seen_speed(room, deceleration=cfg.linear_deceleration,
                                      latency=cfg.sight_latency)
        return max(speed, cfg.min_regulated_speed)

    def _coasting_collides(self, pose: Pose2D, velocity: Twist, costmap: CostGrid) -> bool:
        """While braking into a turn in place, does the robot roll into an obstacle?

        Only asked of a robot that is really moving (above ``standstill_speed``): the arc is the
        one the measured velocity draws, swept by the footprint as it turns along it.
        """
        cfg = self.config
        kappa = velocity.angular / velocity.linear
        step = 0.5 * costmap.info.resolution
        # What it covers while braking, plus the collision lookahead at its speed: a robot
        # really rolling keeps the usual margin, one barely moving gets a barely longer arc.
        reach = regulation.stop_distance(
            velocity.linear,
            deceleration=cfg.linear_deceleration,
            lookahead_time=cfg.collision_lookahead_time,
            minimum=0.0,
        )
        arc = collision.arc_poses(pose, kappa, reach + step, step)
        return collision.first_footprint_collision(self.footprint, costmap, arc) is not None

    def _limit(self, speed: float, kappa: float, velocity: Twist, dt: float) -> Twist:
        """Velocity and acceleration limits, keeping to the arc where the turn rate allows."""
        cfg = self.config
        linear = regulation.limit_linear(
            min(speed, cfg.max_linear_velocity),
            velocity.linear,
            acceleration=cfg.linear_acceleration,
            deceleration=cfg.linear_deceleration,
            dt=dt,
        )
        wanted = linear * kappa
        turn = max(min(wanted, cfg.max_angular_velocity), -cfg.max_angular_velocity)
        angular = regulation.limit_angular(
            turn, velocity.angular, acceleration=cfg.angular_acceleration, dt=dt
        )
        if linear > 0.0 and abs(angular - wanted) > 1e-12:
            # The turn rate cannot follow the arc at this speed: slow down to stay on it (cutting
            # or widening the arc is what makes a robot orbit a goal), as far as braking allows.
            on_arc = angular / kappa if angular * kappa > 0.0 else 0.0
            floor = regulation.limit_linear(
                0.0,
                velocity.linear,
                acceleration=cfg.linear_acceleration,
                deceleration=cfg.linear_deceleration,
                dt=dt,
            )
            linear = min(linear, max(on_arc, floor))
        return Twist(linear, angular)

    def _answer(self, twist: Twist, status: ControlStatus) -> ControlCommand:
        if status is not self._status:
            log.debug("controller %s -> %s", self._status.value if self._status else None,
                      status.value)
            self._status = status
        return ControlCommand(twist, status)
