"""Goal commands of the runtime: single goals, patrols, pause, resume, cancel.

A part of :class:`~polynav.runtime.robot_runtime.RobotRuntime` by subject (it is one class
to its callers); what it shares with the others is declared in
:class:`~polynav.runtime.internals.RuntimeParts`.
"""

from __future__ import annotations

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


class GoalCommands(RuntimeParts):
    def go_to(
        self,
        *,
        point: str | None = None,
        pose: Pose2D | None = None,
        map_name: str | None = None,
        options: GoalOptions | None = None,
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

        Returns:
            The attempt id.

        Raises:
            InvalidRequest: neither or both of ``point`` and ``pose``.
            Conflict: not NAVIGATING.
            NoRoute: (a Conflict) another map that no lift or connection reaches, with the
                reason.
            NotFound: no such map, or no such point on the map.
        """
        if (point is None) == (pose is None):
            raise InvalidRequest("point", "give exactly one of point and pose")
        if pose is not None and not all(math.isfinite(v) for v in (pose.x, pose.y, pose.theta)):
            raise InvalidRequest("pose", "coordinates must be finite")

        def run() -> int:
            self._patrols.end()
            self._patrols.forget()  # the last task is this goal now
            return self._start_goal(point, pose, map_name, options)

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

    def pause(self) -> None:
        """Stop and keep the goal. Raises Conflict when no goal runs."""

        def run() -> None:
            stack = self._require_navigating()
            if not stack.navigator.pause(self.now()):
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
        """Cancel the running or paused goal, or a local move. Raises Conflict if neither."""

        def run() -> None:
            if self._motion.local_move_active:
                self._motion.end_local_move()
                return
            if self._patrols.end():
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
