"""The heuristics of regulated pure pursuit, as pure functions of numbers.

Macenski et al., "Regulated Pure Pursuit for Robot Path Tracking" (Autonomous Robots, 2023), §3,
keep the pure pursuit geometry (steer on the arc through a carrot a lookahead distance ahead) and
*regulate* the linear speed by a few independent factors; each is here, apart from the controller's
state, as Nav2 keeps them in ``regulation_functions.hpp``:

- :func:`lookahead_distance`: the carrot is farther at speed (adaptive pure pursuit);
- :func:`curvature_speed`: slow on tight arcs;
- :func:`proximity_factor`: slow where the costmap says obstacles are near;
- :func:`approach_speed`: slow when the goal is near, down to a floor so the robot gets there;
- :func:`obstacle_speed` and :func:`stop_distance`: slow for, then stop before, an obstacle on the
  path ahead;
- :func:`rotation_speed`: turning in place so that the turn ends on the target heading;
- :func:`limit_linear` and :func:`limit_angular`: what the base can reach in one period.
"""

from __future__ import annotations

import logging
import math

from polynav.maps import costs

log = logging.getLogger(__name__)


def lookahead_distance(
    speed: float, *, lookahead_time: float, min_lookahead: float, max_lookahead: float
) -> float:
    """Lookahead [m]: the distance covered in ``lookahead_time`` [s] at ``speed`` [m/s], bounded."""
    return min(max(abs(speed) * lookahead_time, min_lookahead), max_lookahead)


def curvature(x: float, y: float) -> float:
    """Curvature [1/m] of the arc from the robot (heading +x) through the point (x, y) [m].

    Pure pursuit's one formula, 2y / L² (Coulter, "Implementation of the Pure Pursuit Path
    Tracking Algorithm", CMU-RI-TR-92-01): positive turns left.
    """
    d2 = x * x + y * y
    return 2.0 * y / d2 if d2 > 1e-12 else 0.0


def curvature_speed(speed: float, kappa: float, *, min_radius: float) -> float:
    """``speed`` scaled by turning radius / ``min_radius`` on arcs tighter than ``min_radius``.

    Slowing on tight arcs keeps the robot on them (less overshoot in corners) and gives the
    collision check and people around the robot time where it cannot see far along its path.
    """
    radius = 1.0 / abs(kappa) if abs(kappa) > 1e-9 else math.inf
    if radius < min_radius:
        return speed * radius / min_radius
    return speed


def proximity_factor(cost: int, *, cost_threshold: int, slowdown: float) -> float:
    """Speed factor for an inflation ``cost`` under or just ahead of the robot.

    1 up to ``cost_threshold``, then falling linearly to ``1 - slowdown`` at the highest
    non-obstacle cost (252, just outside the inscribed radius). Inflation costs fall off
    exponentially with distance from an obstacle, so this is Nav2's ``cost_scaling_dist`` idea (slow
    within some distance of obstacles) read directly from the cost, without having to know the
    inflation layer's radius and decay here. INSCRIBED and LETHAL get the strongest slowdown; the
    collision check, not this, decides whether to stop. UNKNOWN does not slow.
    """
    if cost == costs.UNKNOWN or cost <= cost_threshold:
        return 1.0
    c = min(cost, costs.MAX_NON_OBSTACLE)
    return 1.0 - slowdown * (c - cost_threshold) / (costs.MAX_NON_OBSTACLE - cost_threshold)


#: Share of the deceleration limit an approach plans with; the rest is kept in hand for the
#: control period's lag and odometry noise, so the robot stops on the goal, not past it. Each
#: period's slow-down is limited from the *measured* speed, which lags the base by half a physics
#: step while it brakes: a 2 m/s base planning with 75 % shed only ~1.4 m/s², fell behind its
#: curve, reached the goal at ~0.5 m/s and coasted 5-7 cm past (research-base); at half it
#: arrives within 1.4 cm, and the 0.6 m/s demo robot, on its linear ramp there, is unchanged.
APPROACH_BRAKING_SHARE = 0.5


def approach_speed(
    speed: float,
    remaining: float,
    *,
    scaling_distance: float,
    min_speed: float,
    deceleration: float | None = None,
) -> float:
    """``speed`` scaled down within ``scaling_distance`` [m] of the goal, not below ``min_speed``.

    ``remaining`` should be the distance *along the path*, not the straight line, while the path
    still bends: a path that curls back near its own goal would otherwise slow the robot long
    before it gets there (Nav2 ``approachVelocityScalingFactor``).

    With ``deceleration`` [m/s²] the speed is also one the base can still brake from within
    ``remaining`` (``sqrt(2 a d)`` with :data:`APPROACH_BRAKING_SHARE` of the limit): a linear ramp
    over a fixed distance suits a slow robot, but a 2 m/s base needs a metre to stop and would
    overshoot the goal, turn round and come back.
    """
    out = speed
    if remaining < scaling_distance:
        out = min(speed, max(speed * remaining / scaling_distance, min_speed))
    if deceleration is not None and deceleration > 0.0:
        braking = math.sqrt(2.0 * APPROACH_BRAKING_SHARE * deceleration * max(remaining, 0.0))
        out = min(out, max(braking, min_speed))
    return out


def seen_speed(distance: float, *, deceleration: float, latency: float) -> float:
    """The fastest speed [m/s] from which the robot still stops within ``distance`` [m].

    ``distance`` is how far along the way the floor has been seen free. What lies beyond is
    unknown: a wall round a corner is seen only once the robot looks past the corner, and the
    robot must then be able to stop short of it. The robot covers ``latency`` [s] of travel (a
    scan and a control period) before it starts braking at ``deceleration`` [m/s²]: the speed
    solves ``v * latency + v² / (2 a) = distance``.
    """
    if distance <= 0.0:
        return 0.0
    a_t = deceleration * latency
    return -a_t + math.sqrt(a_t * a_t + 2.0 * deceleration * distance)


def stop_distance(
    speed: float, *, deceleration: float, lookahead_time: float, minimum: float
) -> float:
    """Distance [m] ahead within which an obstacle on the path stops the robot.

    What the robot covers in the collision lookahead time plus its braking distance, and never less
    than ``minimum``, so that a slow robot still keeps clear of an obstacle instead of creeping up
    to it.
    """
    v = abs(speed)
    return max(minimum, v * lookahead_time + v * v / (2.0 * deceleration))


def obstacle_speed(
    distance: float,
    *,
    stop_at: float,
    slowdown_distance: float,
    max_speed: float,
    min_speed: float,
) -> float:
    """Speed cap for an obstacle ``distance`` [m] ahead on the path, beyond ``stop_at`` [m].

    Falls linearly from ``max_speed`` at ``slowdown_distance`` to ``min_speed`` at ``stop_at``:
    the robot arrives slowly at the stopping distance, so the stop itself is gentle.
    """
    span = slowdown_distance - stop_at
    if span <= 1e-9 or distance >= slowdown_distance:
        return max_speed
    fraction = max(distance - stop_at, 0.0) / span
    return max(min_speed, max_speed * fraction)


def rotation_speed(
    error: float, *, max_speed: float, acceleration: float, gain: float, min_speed: float
) -> float:
    """Signed turn rate [rad/s] toward a heading ``error`` [rad] away, for turning in place.

    The fastest rate from which the robot can still stop on the heading at ``acceleration``
    (sqrt(2·a·|e|)), also at most ``gain``·|e| so the last part converges gently, and at least
    ``min_speed`` so a real base with static friction still finishes the turn. No error, no turn.
    """
    if error == 0.0:
        return 0.0
    magnitude = min(max_speed, math.sqrt(2.0 * acceleration * abs(error)), gain * abs(error))
    return math.copysign(max(magnitude, min_speed), error)


def limit_linear(
    target: float, current: float, *, acceleration: float, deceleration: float, dt: float
) -> float:
    """``target`` [m/s] as far as the base can go from ``current`` in ``dt`` [s].

    Speeding up (in either direction) is limited by ``acceleration``, slowing down by
    ``deceleration``; a robot still rolling backwards after a back-up is braked, not snapped to
    zero.
    """
    if dt <= 0.0:
        return target
    if current >= 0.0:
        if target >= current:
            return min(target, current + acceleration * dt)
        # Slowing toward zero, then possibly on into reverse: both count as braking here since
        # the controller itself never asks for reverse.
        return max(target, current - deceleration * dt)
    if target <= current:
        return max(target, current - acceleration * dt)
    return min(target, current + deceleration * dt)


def limit_angular(target: float, current: float, *, acceleration: float, dt: float) -> float:
    """``target`` [rad/s] as far as the base can go from ``current`` in ``dt`` [s]."""
    if dt <= 0.0:
        return target
    step = acceleration * dt
    return min(max(target, current - step), current + step)
