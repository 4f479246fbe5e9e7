"""The differential-drive base: velocity limits, acceleration ramps and exact arc motion.

Each physics step the commanded twist is clamped to the speed limits, and each of the two
velocities (forward and turn) ramps toward it: at the acceleration rate while speeding up, at the
(larger) deceleration rate while slowing down, braking through zero first when the command
reverses direction. The ramp is piecewise linear in time, so its exact mean over the step is
known; the base then moves at that mean forward speed and turn rate, which is an exact arc of the
unicycle model (a straight line when the turn rate is zero). For a straight run this is the exact
distance under constant acceleration: braking from ``v`` at rate ``a`` covers ``v² / 2a``.

A step is first *proposed* (:meth:`DiffDrive.propose`) and then *applied*, or not: the
simulation rejects a step whose end pose overlaps an obstacle and stops the base instead.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

from polynav.geometry import Pose2D, Twist
from polynav.robot.sim.config import SimConfig

log = logging.getLogger(__name__)


def ramp(current: float, target: float, dt: float, *, accel: float, decel: float
         ) -> tuple[float, float]:
    """Velocity after ``dt`` moving from ``current`` toward ``target``, and its mean over ``dt``.

    Speeding up (away from zero) runs at ``accel``, slowing down (toward zero) at ``decel``; a
    reversal brakes to zero at ``decel`` and then speeds up at ``accel`` in the same step.

    Args:
        current: velocity now [m/s or rad/s].
        target: commanded velocity, already clamped.
        dt: step [s].
        accel: speeding-up rate [per s²], > 0.
        decel: slowing-down rate [per s²], > 0.

    Returns:
        (velocity at the end of the step, mean velocity over the step).
    """
    v, left, area = current, dt, 0.0
    if v != 0.0 and (target == 0.0 or (target > 0.0) != (v > 0.0) or abs(target) < abs(v)):
        # Slowing: toward the target if it lies on this side of zero, else to zero first.
        stop = target if (target > 0.0) == (v > 0.0) and target != 0.0 else 0.0
        v, used, part = _approach(v, stop, left, decel)
        area += part
        left -= used
    if left > 0.0 and v != target:
        v, used, part = _approach(v, target, left, accel)
        area += part
        left -= used
    area += v * left
    return v, area / dt


def _approach(v: float, target: float, time: float, rate: float) -> tuple[float, float, float]:
    """Move ``v`` toward ``target`` at ``rate`` for at most ``time``: (v, time used, ∫v dt)."""
    need = abs(target - v) / rate
    # The tolerance keeps rounding from leaving a 1e-17 m/s crawl after a whole number of steps.
    if need > time + 1e-12:
        end = v + math.copysign(rate * time, target - v)
        return end, time, 0.5 * (v + end) * time
    used = min(need, time)
    return target, used, 0.5 * (v + target) * used


def integrate_arc(pose: Pose2D, linear: float, angular: float, dt: float) -> Pose2D:
    """Pose after moving at a constant ``linear`` [m/s] and ``angular`` [rad/s] for ``dt`` [s].

    The unicycle's exact solution: an arc of radius ``linear / angular`` (a line when
    ``angular`` is 0).
    """
    turn = angular * dt
    theta = pose.theta
    if abs(turn) < 1e-9:
        # The arc's chord heads along the mid-step heading; the error is O(turn²), below 1e-18.
        mid = theta + 0.5 * turn
        return Pose2D(pose.x + linear * dt * math.cos(mid),
                      pose.y + linear * dt * math.sin(mid), theta + turn)
    radius = linear / angular
    return Pose2D(
        pose.x + radius * (math.sin(theta + turn) - math.sin(theta)),
        pose.y - radius * (math.cos(theta + turn) - math.cos(theta)),
        theta + turn,
    )


@dataclass(frozen=True, slots=True)
class MotionStep:
    """A proposed step of the base: where it would end and how it would get there.

    Attributes:
        pose: pose at the end of the step.
        twist: velocities at the end of the step.
        distance: signed distance travelled along the arc [m].
        rotation: signed heading change [rad].
        dt: step length [s].
    """

    pose: Pose2D
    twist: Twist
    distance: float
    rotation: float
    dt: float


class DiffDrive:
    """A differential-drive base: true pose, true velocity, and the limits that shape them."""

    def __init__(self, config: SimConfig, pose: Pose2D) -> None:
        self.config = config
        self.pose = pose
        self.twist = Twist()

    def clamp(self, command: Twist) -> Twist:
        """The command limited to the base's top speeds."""
        c = self.config
        return Twist(
            max(-c.max_linear_velocity, min(c.max_linear_velocity, command.linear)),
            max(-c.max_angular_velocity, min(c.max_angular_velocity, command.angular)),
        )

    def propose(self, command: Twist, dt: float) -> MotionStep:
        """Where one step of ``dt`` [s] toward ``command`` would take the base; changes nothing."""
        c = self.config
        # What clamp() computes, without building a Twist every physics step.
        linear = max(-c.max_linear_velocity, min(c.max_linear_velocity, command.linear))
        angular = max(-c.max_angular_velocity, min(c.max_angular_velocity, command.angular))
        v, v_mean = ramp(self.twist.linear, linear, dt,
                         accel=c.linear_acceleration, decel=c.linear_deceleration)
        w, w_mean = ramp(self.twist.angular, angular, dt,
                         accel=c.angular_acceleration, decel=c.angular_deceleration)
        return MotionStep(
            pose=integrate_arc(self.pose, v_mean, w_mean, dt),
            twist=Twist(v, w),
            distance=v_mean * dt,
            rotation=w_mean * dt,
            dt=dt,
        )

    def apply(self, step: MotionStep) -> None:
        """Make a proposed step real."""
        self.pose = step.pose
        self.twist = step.twist

    def halt(self) -> None:
        """Stop dead where the base stands (a collision)."""
        self.twist = Twist()

    def place(self, pose: Pose2D) -> None:
        """Put the base at ``pose``, at rest (a lift ride, a test)."""
        self.pose = pose
        self.twist = Twist()
