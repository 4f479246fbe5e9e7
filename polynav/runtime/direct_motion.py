"""Direct motion: the velocities the runtime commands itself when no goal drives the robot.

Two kinds exist, and at most one runs: a teleop command (held for its timeout, the dead-man)
and a local move (turn by an angle or drive a distance, :mod:`polynav.runtime.local_move`).
:class:`DirectMotion` starts and ends them on the base and, each control tick, says which
velocity overrides the navigation stack's.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable

from polynav.geometry import Twist
from polynav.robot.interface import Robot
from polynav.runtime.local_move import LocalMove
from polynav.runtime.settings import RobotSettings
from polynav.runtime.teleop import Teleop

log = logging.getLogger(__name__)

FreeAhead = Callable[[float, float], float]
"""How far [m] the way is clear in a ``direction`` (+1 forward, -1 backward), looking at most
``remaining`` [m] (plus the stop distance) ahead."""


class DirectMotion:
    """Teleop and local moves on one base.

    Args:
        robot: the base to drive.
        teleop_timeout: how long [s] one teleop command holds.
    """

    def __init__(self, robot: Robot, teleop_timeout: float) -> None:
        self._robot = robot
        self._teleop = Teleop(teleop_timeout)
        self._local_move: LocalMove | None = None

    @property
    def local_move_active(self) -> bool:
        return self._local_move is not None

    def teleop(self, twist: Twist, now: float) -> None:
        """Drive at ``twist`` from now for the teleop timeout; a local move ends."""
        self.end_local_move()
        self._teleop.command(twist, now)
        self._robot.drive(twist)

    def start_local_move(
        self, *, rotate: float | None, distance: float | None, settings: RobotSettings
    ) -> None:
        """Start turning by ``rotate`` [rad] or driving ``distance`` [m] within the settings'
        limits; teleop and a local move already running end."""
        self.yield_control()
        self._local_move = LocalMove(
            rotate=rotate,
            distance=distance,
            yaw=self.yaw(),
            odometry_pose=self._robot.read_odometry().pose,
            max_linear_velocity=settings.max_linear_velocity,
            max_angular_velocity=settings.max_angular_velocity,
            stop_distance=settings.obstacle_stop_distance,
        )

    def yield_control(self) -> None:
        """End teleop and any local move, for something else to drive (a goal, a new move);
        teleop ends without a brake command, as what comes next drives at once."""
        self._teleop.stop()
        self.end_local_move()

    def halt(self) -> None:
        """End teleop and any local move and brake."""
        if self._teleop.active:
            self._teleop.stop()
            self._robot.drive(Twist())
        self.end_local_move()

    def end_local_move(self) -> None:
        """Cancel a local move, braking; nothing when none runs."""
        if self._local_move is not None:
            self._local_move.cancel()
            self._local_move = None
            self._robot.drive(Twist())

    def brake_if_expired(self, now: float) -> None:
        """The dead-man: brake at once when a teleop command has timed out."""
        if self._teleop.active and self._teleop.twist(now) is None:
            self._robot.drive(Twist())  # brake now, not at the next control tick

    def override(self, now: float, estop: bool, free_ahead: FreeAhead) -> Twist | None:
        """The velocity that overrides the navigation stack's this control tick, if any.

        An e-stop ends all direct motion (``None``: the stack holds the robot). A finished or
        blocked local move yields one zero twist.
        """
        if estop:
            self.halt()
            return None
        twist = self._teleop.twist(now)
        if twist is not None:
            return twist
        move = self._local_move
        if move is None:
            return None
        odometry = self._robot.read_odometry().pose
        remaining = move.remaining(odometry)
        free = math.inf
        if move.distance is not None:
            free = free_ahead(math.copysign(1.0, remaining), abs(remaining))
        twist = move.tick(yaw=self.yaw(), odometry_pose=odometry, free_ahead=free)
        if twist is None:
            self._local_move = None
            return Twist()
        return twist

    def yaw(self) -> float:
        """The robot's heading from the IMU, else from wheel odometry [rad]."""
        imu = self._robot.read_imu()
        return imu.yaw if imu is not None else self._robot.read_odometry().pose.theta
