"""Local moves: turn on the spot by an angle, or drive straight a distance, then stop.

Operators use these to nudge a robot (Galileo's and Yunji's "rotate" and "move" commands, the
last centimetres onto a dock). A :class:`LocalMove` measures its progress on the robot's own
sensors, which do not jump the way a localization estimate can: the IMU's integrated yaw for
turns and for holding the heading, wheel odometry for distance. Speeds follow a profile that
brakes in time, ``v = min(v_max, k·e, sqrt(2·a·e))`` for a remaining error ``e``, so the move
ends within a centimetre or a hundredth of a radian without overshooting.

Before each step the runtime measures how far the way is clear in the direction of travel
(:func:`free_distance_on_costmap` while a map is loaded, so virtual walls count too;
:func:`free_distance_in_scan` otherwise); a straight move that would come closer than its stop
distance to an obstacle ends as ``BLOCKED``.
"""

from __future__ import annotations

import enum
import logging
import math
from dataclasses import dataclass, fields
from typing import Protocol

import numpy as np

from polynav.errors import ConfigError
from polynav.geometry import Pose2D, Twist, angle_diff
from polynav.maps import costs
from polynav.robot.interface import LaserScan

log = logging.getLogger(__name__)


class LocalMoveOutcome(enum.Enum):
    RUNNING = "running"
    DONE = "done"
    BLOCKED = "blocked"
    CANCELED = "canceled"


@dataclass(frozen=True, slots=True)
class LocalMoveConfig:
    """Profile and tolerances of local moves [m, rad, s].

    Attributes:
        distance_tolerance: a straight move ends this close [m] to its distance.
        angle_tolerance: a turn ends this close [rad] to its angle.
        gain: proportional gain [1/s] on the remaining error near the end.
        linear_deceleration: braking assumed by the profile [m/s²], below the base's own.
        angular_deceleration: turn braking assumed by the profile [rad/s²].
        min_linear_velocity: slowest forward speed [m/s] (static friction of real bases).
        min_angular_velocity: slowest turn rate [rad/s].
        heading_gain: heading hold on straight moves [1/s].
    """

    distance_tolerance: float = 0.01
    angle_tolerance: float = 0.01
    gain: float = 2.0
    linear_deceleration: float = 0.5
    angular_deceleration: float = 2.0
    min_linear_velocity: float = 0.03
    min_angular_velocity: float = 0.08
    heading_gain: float = 2.0

    def __post_init__(self) -> None:
        for f in fields(self):
            name, value = f.name, getattr(self, f.name)
            if not (math.isfinite(value) and value > 0.0):
                raise ConfigError(f"runtime.local_move.{name}", f"must be > 0, got {value}")


class LocalMove:
    """One turn or one straight move, from where the robot stands now.

    Args:
        rotate: angle to turn [rad], counter-clockwise positive; any size (2π is a full turn).
        distance: distance to drive [m], negative backwards.
        yaw: the IMU's integrated yaw [rad] at the start.
        odometry_pose: the odometry pose at the start.
        max_linear_velocity, max_angular_velocity: the robot's speed settings.
        stop_distance: a straight move ends blocked when the way is clear for less than this [m]
            and less than the distance still to go.
        config: profile and tolerances.
    """

    def __init__(
        self,
        *,
        rotate: float | None,
        distance: float | None,
        yaw: float,
        odometry_pose: Pose2D,
        max_linear_velocity: float,
        max_angular_velocity: float,
        stop_distance: float,
        config: LocalMoveConfig | None = None,
    ) -> None:
        self.config = config or LocalMoveConfig()
        self.rotate = rotate
        self.distance = distance
        self._start = odometry_pose
        self._heading = yaw
        self._last_yaw = yaw
        self._turned = 0.0
        self._max_v = max_linear_velocity
        self._max_w = max_angular_velocity
        self._stop_distance = stop_distance
        self.outcome = LocalMoveOutcome.RUNNING

    @property
    def direction(self) -> float:
        """+1 forward, -1 backward, 0 for a turn."""
        if self.distance is None:
            return 0.0
        return math.copysign(1.0, self.distance)

    def remaining(self, odometry_pose: Pose2D) -> float:
        """Distance [m] still to drive (signed like ``distance``); 0 for a turn."""
        if self.distance is None:
            return 0.0
        c, s = math.cos(self._start.theta), math.sin(self._start.theta)
        done = (odometry_pose.x - self._start.x) * c + (odometry_pose.y - self._start.y) * s
        return self.distance - done

    def cancel(self) -> None:
        if self.outcome is LocalMoveOutcome.RUNNING:
            self.outcome = LocalMoveOutcome.CANCELED

    def tick(self, *, yaw: float, odometry_pose: Pose2D, free_ahead: float) -> Twist | None:
        """The velocity for this control period, or ``None`` once the move has ended.

        Args:
            yaw: the IMU's integrated yaw [rad] now.
            odometry_pose: the odometry pose now.
            free_ahead: how far [m] the way is clear in the direction of travel (ignored by
                turns).
        """
        if self.outcome is not LocalMoveOutcome.RUNNING:
            return None
        cfg = self.config
        self._turned += angle_diff(yaw, self._last_yaw)
        self._last_yaw = yaw
        if self.distance is None:
            error = (self.rotate or 0.0) - self._turned
            if abs(error) <= cfg.angle_tolerance:
                self._end(LocalMoveOutcome.DONE)
                return None
            w = _profile(abs(error), cfg.gain, cfg.angular_deceleration, self._max_w,
                         cfg.min_angular_velocity)
            return Twist(0.0, math.copysign(w, error))
        remaining = self.remaining(odometry_pose)
        if abs(remaining) <= cfg.distance_tolerance:
            self._end(LocalMoveOutcome.DONE)
            return None
        if math.copysign(1.0, remaining) == self.direction and (
            free_ahead < abs(remaining) and free_ahead <= self._stop_distance
        ):
            log.info("local move blocked: %.2f m clear, %.2f m to go", free_ahead, remaining)
            self._end(LocalMoveOutcome.BLOCKED)
            return None
        v = _profile(abs(remaining), cfg.gain, cfg.linear_deceleration, self._max_v,
                     cfg.min_linear_velocity)
        heading_error = angle_diff(self._heading, yaw)
        w = max(-self._max_w, min(self._max_w, cfg.heading_gain * heading_error))
        return Twist(math.copysign(v, remaining), w)

    def _end(self, outcome: LocalMoveOutcome) -> None:
        self.outcome = outcome
        log.info("local move %s", outcome.value)


def _profile(error: float, gain: float, decel: float, top: float, bottom: float) -> float:
    return max(bottom, min(top, gain * error, math.sqrt(2.0 * decel * error)))


class _Costs(Protocol):
    def cost_at(self, x: float, y: float) -> int: ...


def free_distance_on_costmap(
    costmap: _Costs,
    pose: Pose2D,
    *,
    direction: float,
    robot_radius: float,
    horizon: float,
    step: float,
) -> float:
    """How far [m] the robot's edge can move along its heading before touching a lethal cell.

    Args:
        costmap: anything with ``cost_at(x, y)`` (LETHAL outside the map).
        pose: the robot's pose on the costmap's map.
        direction: +1 forward, -1 backward.
        robot_radius: the footprint's radius [m].
        horizon: look no farther than this [m] for the robot's centre.
        step: sampling step [m], at most half a cell.

    Returns:
        The clear distance, ``inf`` when nothing lethal lies within the horizon.
    """
    c, s = math.cos(pose.theta) * direction, math.sin(pose.theta) * direction
    for d in np.arange(0.0, horizon + robot_radius + step, step):
        if costmap.cost_at(pose.x + c * d, pose.y + s * d) >= costs.LETHAL:
            return max(0.0, float(d) - robot_radius)
    return math.inf


def free_distance_in_scan(scan: LaserScan, *, direction: float, robot_radius: float) -> float:
    """How far [m] the robot's edge can move straight before touching a scanned return.

    Returns within the robot's width (a corridor ``2·robot_radius`` wide, robot frame) count;
    ``inf`` when none lies ahead (or behind, for ``direction`` -1).
    """
    ranges = scan.ranges.astype(np.float64)
    ok = np.isfinite(ranges)
    if not ok.any():
        return math.inf
    angles = scan.angles[ok] + scan.sensor_pose.theta
    r = ranges[ok]
    x = scan.sensor_pose.x + r * np.cos(angles)
    y = scan.sensor_pose.y + r * np.sin(angles)
    ahead = x * direction
    hit = (ahead > 0.0) & (np.abs(y) < robot_radius)
    if not hit.any():
        return math.inf
    # The edge of a disk meets a return at lateral offset y after moving x - sqrt(R² - y²).
    reach = ahead[hit] - np.sqrt(robot_radius**2 - y[hit] ** 2)
    return max(0.0, float(reach.min()))
