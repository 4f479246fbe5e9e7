"""Goal commands of the runtime: single goals, patrols, pause, resume, cancel.

A part of :class:`~polynav.runtime.robot_runtime.RobotRuntime` by subject (it is one class
to its callers); what it shares with the others is declared in
:class:`~polynav.runtime.internals.RuntimeParts`.

A goal pose is in a :class:`GoalFrame`: the frame the robot navigates in (``map`` on a map,
``odom`` without one, the default), or ``robot``, relative to where the robot stands when the
goal is given ("10 m ahead" whatever its heading). The runtime turns a robot-frame goal into the
navigation frame through its pose estimate at that instant, between ticks, so adapters only name
the frame and never do the geometry.
"""

from __future__ import annotations

import enum
import math
from dataclasses import replace

from polynav.errors import Conflict, InvalidRequest
from polynav.geometry import Pose2D
from polynav.nav.attempt import GoalOptions, NavigationState
from polynav.nav.stack import NavigationStack
from polynav.runtime.config import Mode
from polynav.runtime.internals import RuntimeParts
from polynav.site import PointKind
from polynav.tasks.patrol import PatrolPlan

UNDOCK_DISTANCE = 0.5
"""How far [m] a robot backs straight off its charger before it plans (clear of the dock)."""


class GoalFrame(enum.Enum):
    """The frame a goal pose is given in."""

    MAP = "map"
    """The map navigation runs on (its name is the status's ``map``)."""
    ODOM = "odom"
    """The odometry frame of navigation without a map: (0, 0, 0) where the robot was switched
    on (the simulated one: created)."""
    ROBOT = "robot"
    """The robot's own frame when the goal is given: x ahead, y to the left, theta from its
    heading [m, rad]."""


class GoalCommands(RuntimeParts):
    _mapless: bool

    def go_to(
        self,
        *,
        point: str | None = None,
        pose: Pose2D | None = None,
        map_name: str | None = None,
        options: GoalOptions | None = None,
        frame: GoalFrame | None = None,
    ) -> int:
        """Start a goal to a point of the current map, or to a pose on it; a goal already
        running is canceled first.

        A robot on a charger backs off it first; a charger point is docked onto (its pose is
        the docked pose, its heading the docking direction).

        Args:
            point: the goal point's name.
            pose: the goal pose (map frame).
            map_name: the map ``point`` or ``pose`` is on; on another map than the current one
                the goal is routed across the site's lifts and connections (see
                :mod:`~polynav.runtime.lift_commands`): one attempt to the caller.
            options: tolerances and retries for this goal (see
                :class:`~polynav.nav.attempt.GoalOptions`).
            frame: the frame of ``pose``; ``None`` is the current navigation frame. ``ROBOT``
                is relative to the robot's pose estimate now (on a map as without one); the
                attempt's goal is then that pose in the navigation frame.

        Returns:
            The attempt id.

        Raises:
            InvalidRequest: neither or both of ``point`` and ``pose``; a frame with a point; a
                robot-frame goal on another map.
            Conflict: not NAVIGATING; ``MAP`` or ``ODOM`` that is not the current frame.
            NoRoute: (a Conflict) another map that no lift or connection reaches, with the
                reason.
            NotFound: no such map, or no such point on the map.
        """
        if (point is None) == (pose is None):
            raise InvalidRequest("point", "give exactly one of point and pose")
        if pose is not None and not all(math.isfinite(v) for v in (pose.x, pose.y, pose.theta)):
            raise InvalidRequest("pose", "coordinates must be finite")
        if frame is not None and point is not None:
            raise InvalidRequest("frame", "a point is named on its map: give a frame with a pose")

        def run() -> int:
            goal = pose if pose is None or frame is None else self._in_navigation_frame(
                pose, frame, map_name)
            self.tasks.engine.give_way("cancelled: a goal was sent")
            if not self.tasks.engine.acting:
                self._patrols.forget()  # the last task is this goal now
            return self._start_goal(point, goal, map_name, options)

        return self._call(run)

    def patrol(
        self, plan: PatrolPlan, options: GoalOptions | None = None
    ) -> int:
        """Patrol ``plan``'s points of the current map, one goal per point, ``plan.count``
        rounds; a running goal or patrol is canceled first.

        Each point is passed within ``plan.tolerance`` [m] (a charger point is docked onto), a
        failed leg is skipped, and :meth:`cancel` ends the whole patrol. ``options`` apply to
        every leg (retries). Events: ``patrol_started``, the legs' navigation events, then
        ``patrol_finished``, ``patrol_failed`` (the last leg failed) or ``patrol_canceled``.

        Returns:
            The patrol id.

        Raises:
            InvalidRequest: fewer than 2 points, a bad count or tolerance.
            NotFound: a point not on the current map.
            Conflict: not NAVIGATING.
        """

        def run() -> int:
            self._require_navigating()
            assert self._map_name is not None
            for name in plan.points:
                self.store.point(self._map_name, name)  # NotFound before anything changes
            return self._patrols.start(plan, options)

        return self._call(run)

    def pause(self, *, make_way: bool = False) -> None:
        """Stop and keep the goal. Raises Conflict when no goal runs. ``make_way``: a wait in
        line (the fleet's traffic rule), in which the robot still steps aside for someone it
        holds up; an operator's pause stays a standstill."""

        def run() -> None:
            stack = self._require_navigating()
            if not stack.navigator.pause(self.now(), make_way=make_way):
                raise Conflict("no running goal to pause")

        self._call(run)

    def resume(self) -> None:
        """Continue a paused goal. Raises Conflict when no goal is paused."""

        def run() -> None:
            stack = self._require_navigating()
            if not stack.navigator.resume(self.now()):
                raise Conflict("no paused goal to resume")

        self._call(run)

    def cancel(self) -> None:
        """Cancel the running task (with what it drives), else the running or paused goal, or
        a local move. Raises Conflict if none runs."""

        def run() -> None:
            if self.tasks.engine.give_way("cancelled"):
                return  # the task's goal or local move with it
            if self._motion.local_move_active:
                self._motion.end_local_move()
                return
            if not self._cancel_goal():
                raise Conflict("no goal or local move to cancel")

        self._call(run)

    def _start_goal(
        self,
        point: str | None,
        pose: Pose2D | None,
        map_name: str | None,
        options: GoalOptions | None,
    ) -> int:
        stack = self._require_navigating()
        assert self._map_name is not None
        target_map = map_name or self._map_name
        goal_options = options or GoalOptions()
        if target_map != self._map_name:
            self.store.map_record(target_map)  # NotFound for an unknown map, point or not
        if point is not None:
            record = self.store.point(target_map, point)
            goal = record.pose
            if record.kind is PointKind.CHARGER:
                goal_options = replace(goal_options, dock=True, pass_tolerance=None)
        else:
            assert pose is not None
            goal = pose
        if goal_options.undock_distance is None and self._robot.read_battery().charging:
            goal_options = replace(goal_options, undock_distance=UNDOCK_DISTANCE)
        self._motion.yield_control()
        if self._settings_dirty:
            self._cancel_goal()
            stack = self._rebuild_stack()
        if target_map != self._map_name:
            return self._start_route(point, goal, target_map, goal_options)
        self._end_route(NavigationState.CANCELED)
        self._attempts.pending_point = point
        try:
            nav_id = stack.go_to(goal, self.now(), goal_options)
        finally:
            self._attempts.pending_point = None
        return self._attempts.runtime_id(nav_id)

    def _navigation_frame(self) -> GoalFrame:
        """The frame goals and the pose estimate are in now."""
        return GoalFrame.ODOM if self._mapless else GoalFrame.MAP

    def _in_navigation_frame(self, pose: Pose2D, frame: GoalFrame, map_name: str | None) -> Pose2D:
        """``pose`` given in ``frame``, as a goal in the frame the robot navigates in."""
        stack = self._require_navigating()
        current = self._navigation_frame()
        if frame is GoalFrame.ROBOT:
            if map_name is not None and map_name != self._map_name:
                raise InvalidRequest("frame", "a goal relative to the robot is on the robot's "
                                              f"map ({self._map_name!r}), not on {map_name!r}")
            # The estimate, not the odometry: on a map it is the pose the goal must be on, and
            # without one it is the odometry corrected by scan matching, in the same frame.
            return stack.estimate.pose.compose(pose)
        if frame is not current:
            hint = ("navigating without a map: there is no map frame"
                    if self._mapless else "navigating on a map: goals are on the map")
            raise Conflict(f"a goal in the {frame.value!r} frame, but {hint}; give it in "
                           f"{current.value!r} or relative to the robot ('robot')")
        return pose

    def _cancel_goal(self) -> bool:
        if self._end_route(NavigationState.CANCELED):
            return True
        if self._stack is None:
            return False
        return self._stack.navigator.cancel(self.now())

    def _goal_active(self) -> bool:
        if self._route_running():
            return True
        return self._stack is not None and self._stack.navigator.state in (
            NavigationState.RUNNING,
            NavigationState.PAUSED,
        )

    def _require_navigating(self) -> NavigationStack:
        if self._mode is not Mode.NAVIGATING or self._stack is None:
            raise Conflict(f"not navigating (mode {self._mode.value}): start navigation first")
        return self._stack
