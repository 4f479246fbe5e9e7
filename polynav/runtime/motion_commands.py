"""Direct motion commands of the runtime: teleop, the software e-stop, local moves.

A part of :class:`~polynav.runtime.robot_runtime.RobotRuntime` by subject (it is one class
to its callers); what it shares with the others is declared in
:class:`~polynav.runtime.internals.RuntimeParts`.
"""

from __future__ import annotations

import logging
import math

from polynav.errors import Conflict, InvalidRequest
from polynav.geometry import Twist
from polynav.runtime.config import Mode
from polynav.runtime.internals import RuntimeParts
from polynav.runtime.local_move import free_distance_in_scan, free_distance_on_costmap

log = logging.getLogger(__name__)

_MAX_LOCAL_ROTATION = 4.0 * math.pi
_MAX_LOCAL_DISTANCE = 10.0


class MotionCommands(RuntimeParts):
    @property
    def local_move_active(self) -> bool:
        """Whether a local move is under way (task runners wait for it to end)."""
        return self._motion.local_move_active

    def teleop(self, linear: float, angular: float) -> None:
        """Drive at ``linear`` [m/s], ``angular`` [rad/s] (clamped to the settings) for
        ``teleop_timeout`` seconds; repeat the command to keep moving (dead-man).

        A local move in progress ends. A goal is not overridden silently: cancel it first.

        Raises:
            InvalidRequest: a value that is not finite.
            Conflict: a goal is running or paused; an e-stop is active; BUSY.
        """
        for key, value in (("linear", linear), ("angular", angular)):
            if isinstance(value, bool) or not math.isfinite(value):
                raise InvalidRequest(key, f"must be a finite number, got {value!r}")

        def run() -> None:
            self._check_free_to_move("teleop")
            s = self._settings
            twist = Twist(
                max(-s.max_linear_velocity, min(s.max_linear_velocity, float(linear))),
                max(-s.max_angular_velocity, min(s.max_angular_velocity, float(angular))),
            )
            self._motion.teleop(twist, self.now())

        self._call(run)

    def set_software_estop(self, on: bool) -> None:
        """Switch the software e-stop (distinct from the hardware button): the base brakes,
        teleop and local moves end, a goal is held until it is switched off."""

        def run() -> None:
            self._software_estop = bool(on)
            if self._stack is not None:
                self._stack.software_estop = self._software_estop
            if on:
                self._halt_motion()
            self._check_estop(self.now())

        self._call(run)

    def local_move(
        self, *, rotate: float | None = None, distance: float | None = None
    ) -> None:
        """Turn on the spot by ``rotate`` [rad] or drive straight ``distance`` [m] (negative:
        backwards), checked against obstacles (the costmap while NAVIGATING, else the scan);
        ends by itself, or blocked, or on :meth:`cancel`.

        Raises:
            InvalidRequest: neither or both; not finite; more than 4π rad or 10 m.
            Conflict: a goal is running or paused; an e-stop is active; BUSY.
        """
        if (rotate is None) == (distance is None):
            raise InvalidRequest("rotate", "give exactly one of rotate and distance")
        if rotate is not None and not (
            math.isfinite(rotate) and abs(rotate) <= _MAX_LOCAL_ROTATION
        ):
            raise InvalidRequest("rotate", f"must be finite and within ±4π, got {rotate}")
        if distance is not None and not (
            math.isfinite(distance) and abs(distance) <= _MAX_LOCAL_DISTANCE
        ):
            raise InvalidRequest("distance", f"must be finite and within ±10 m, got {distance}")

        def run() -> None:
            self._check_free_to_move("local move")
            self._motion.start_local_move(
                rotate=rotate, distance=distance, settings=self._settings
            )
            log.info("local move: rotate %s rad, distance %s m", rotate, distance)

        self._call(run)

    def _free_ahead(self, direction: float, remaining: float) -> float:
        s = self._settings
        stack = self._stack
        if stack is not None:
            return free_distance_on_costmap(
                stack.costmap,
                stack.estimate.pose,
                direction=direction,
                robot_radius=s.robot_radius,
                horizon=remaining + s.obstacle_stop_distance,
                step=0.5 * stack.costmap.info.resolution,
            )
        scan = self._robot.read_scan()
        if scan is None:
            return math.inf
        return free_distance_in_scan(scan, direction=direction, robot_radius=s.robot_radius)

    def _check_free_to_move(self, what: str) -> None:
        if self._mode is Mode.BUSY:
            raise Conflict(f"the robot is busy: no {what}")
        if self._goal_active():
            raise Conflict(f"a goal is active: cancel it before {what}")
        if self._estop.hardware or self._software_estop:
            raise Conflict(f"the e-stop is active: no {what}")

    def _halt_motion(self) -> None:
        self._motion.halt()
