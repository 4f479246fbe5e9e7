"""Smoothing of the pose estimate the controller steers by: odometry-predicted, estimate-corrected.

The controller stops on the goal by comparing the estimated pose with it, centimetre by centimetre.
A localization estimate that jitters by a centimetre or two from one period to the next would make
that decision on noise: the first lucky sample inside the aim ends the approach, wherever the
robot truly is, and near the goal the bearing to it swings wildly. The robot's own motion over one
period, on the other hand, is known to the millimetre from the measured velocity.

So each period the previous smoothed pose is moved by the measured velocity (the exact unicycle
arc over ``dt``), then pulled toward the new estimate by ``gain``: a complementary filter. Motion
passes without lag (it is predicted), white estimate noise is divided by about sqrt((2 - g) / g)
(3 for g = 0.2), and a correction of the estimate (a scan match moving it) is followed within
about 1 / g periods. A jump farther than ``reset_distance`` (relocalization, a new start) is taken
at once. A gain of 1 turns smoothing off.
"""

from __future__ import annotations

import logging
import math

from polynav.geometry import Pose2D, Twist, angle_diff

log = logging.getLogger(__name__)


class PoseFilter:
    """The smoothed pose; :meth:`update` once per control period."""

    def __init__(self, gain: float, reset_distance: float) -> None:
        """
        Args:
            gain: weight (0, 1] of a new estimate against the prediction.
            reset_distance: a new estimate farther than this [m] from the prediction replaces it.
        """
        self.gain = gain
        self.reset_distance = reset_distance
        self._pose: Pose2D | None = None

    def update(self, estimate: Pose2D, velocity: Twist, dt: float) -> Pose2D:
        """The smoothed pose from the new ``estimate`` and the velocity over the last ``dt`` [s]."""
        if self._pose is None or self.gain >= 1.0:
            self._pose = estimate
            return estimate
        predicted = _advance(self._pose, velocity, dt)
        if predicted.distance_to(estimate) > self.reset_distance:
            self._pose = estimate
            return estimate
        g = self.gain
        self._pose = Pose2D(
            predicted.x + g * (estimate.x - predicted.x),
            predicted.y + g * (estimate.y - predicted.y),
            predicted.theta + g * angle_diff(estimate.theta, predicted.theta),
        )
        return self._pose

    def reset(self) -> None:
        """Forget the smoothed pose: the next estimate is taken as it is."""
        self._pose = None


def _advance(pose: Pose2D, velocity: Twist, dt: float) -> Pose2D:
    """``pose`` moved along the exact arc of ``velocity`` for ``dt`` [s]."""
    v, w = velocity.linear, velocity.angular
    if dt <= 0.0:
        return pose
    if abs(w) < 1e-9:
        return Pose2D(pose.x + v * dt * math.cos(pose.theta),
                      pose.y + v * dt * math.sin(pose.theta), pose.theta)
    theta = pose.theta + w * dt
    return Pose2D(pose.x + v / w * (math.sin(theta) - math.sin(pose.theta)),
                  pose.y - v / w * (math.cos(theta) - math.cos(pose.theta)), theta)
