"""Simulated wheel odometry: the true motion of each step, integrated with noise.

Odometry lives in its own ``odom`` frame, which starts at (0, 0, 0) where the base is created, as
a real base's encoders count from zero where it is switched on; it knows nothing of the map, and
the simulator's ground truth stays in the world frame (``Simulation.odometry_origin`` is where the
frame started, for tests that give goals in world coordinates). Each physics step the base's
true travel ``d`` and turn ``a`` become ``d (1 + σ_t n₁) + ε_t n₂`` and ``a (1 + σ_r n₃) + ε_r n₄``
(``n`` standard normal): wheel slip and encoder error scale with the motion, plus a small floor of
quantisation noise. A base at rest reads no motion at all, as encoders that do not tick, so a
parked robot's odometry does not wander. The noisy increments are integrated as arcs, so the drift
grows with distance like real odometry. A teleport (a lift ride) is not motion: odometry does not
see it.
"""

from __future__ import annotations

import logging

import numpy as np

from polynav.geometry import Pose2D, Twist
from polynav.robot.interface import Odometry
from polynav.robot.sim.config import SimConfig
from polynav.robot.sim.diff_drive import integrate_arc

log = logging.getLogger(__name__)


class WheelOdometry:
    """Noisy dead reckoning of the base's true motion."""

    def __init__(self, config: SimConfig, rng: np.random.Generator, stamp: float = 0.0) -> None:
        self._config = config
        self._rng = rng
        self._reading = Odometry(stamp=stamp, pose=Pose2D(), twist=Twist())

    @property
    def reading(self) -> Odometry:
        """The newest odometry: pose in the odom frame and the measured velocity."""
        return self._reading

    def update(self, distance: float, rotation: float, dt: float, stamp: float) -> None:
        """Add one step's true motion.

        Args:
            distance: signed travel along the arc [m].
            rotation: signed heading change [rad].
            dt: step length [s].
            stamp: time at the end of the step [s].
        """
        if distance == 0.0 and rotation == 0.0:
            self._reading = Odometry(stamp=stamp, pose=self._reading.pose, twist=Twist())
            return
        c = self._config
        n = self._rng.standard_normal(4).tolist()
        d = distance * (1.0 + c.odom_translation_noise * n[0]) + c.odom_translation_additive * n[1]
        a = rotation * (1.0 + c.odom_rotation_noise * n[2]) + c.odom_rotation_additive * n[3]
        pose = integrate_arc(self._reading.pose, d / dt, a / dt, dt)
        self._reading = Odometry(stamp=stamp, pose=pose, twist=Twist(d / dt, a / dt))
