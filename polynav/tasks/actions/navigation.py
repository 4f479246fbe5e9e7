"""Actions that drive the robot to a place: ``nav_action``, ``none_stop_nav_action``,
``charge_action`` and ``switch_map_action`` (galileo-tasks-bt-ws §5.3 #5, #6, #9, #14).

A goal on another map than the one in use is one ``nav_action``: the runtime's router takes
it across direct connections and lifts. Goals that cannot be reached (no path, blocked, stuck,
goal occupied, a map no connection reaches) end ``FAIL``; faults (lost localization, the e-stop,
a refused start because the robot is not navigating) end ``ERROR``. A goal cancelled by someone
else (another client took the robot) cancels the whole task.

Blackboard: on arrival ``nav.x``, ``nav.y``, ``nav.theta`` (the pose reached, map frame).
"""

from __future__ import annotations

import builtins
from dataclasses import replace
from typing import Any, ClassVar

from pydantic import Field, model_validator

from polynav.errors import PolynavError
from polynav.geometry import Pose2D, wrap_angle
from polynav.nav.attempt import FailureReason, GoalOptions
from polynav.routing.errors import NoRoute
from polynav.tasks.action import Action, Params, action_type
from polynav.tasks.node import Run
from polynav.tasks.robot import GoalEnd
from polynav.tasks.states import NodeState

#: Failures that are faults of the robot, not of the goal: ``ERROR``.
FAULTS = frozenset({FailureReason.LOCALIZATION_LOST.value, FailureReason.ESTOP.value,
                    FailureReason.UNDOCK_FAILED.value})


class GoalParams(Params):
    """A pose (``x``, ``y``, ``theta``) or a named ``point``, on ``map`` (default: the one in
    use)."""

    x: float | None = None
    y: float | None = None
    theta: float = 0.0
    point: str | None = Field(default=None, min_length=1)
    map: str | None = Field(default=None, min_length=1)

    @model_validator(mode="after")
    def _one_goal(self) -> GoalParams:
        has_pose = self.x is not None or self.y is not None
        if has_pose and (self.x is None or self.y is None):
            raise ValueError("give both x and y")
        if has_pose == (self.point is not None):
            raise ValueError("give a pose (x, y, theta) or a point, not both")
        return self


class _Goal(Action):
    """A navigation goal: started at :meth:`begin`, followed until it ends."""

    schema: ClassVar[builtins.type[Params]] = GoalParams
    writes = ("nav.x", "nav.y", "nav.theta")

    def __init__(self, params: dict[str, Any], *, options: GoalOptions | None = None,
                 **kwargs: Any) -> None:
        super().__init__(params, **kwargs)
        self.attempt_id: int | None = None
        self._total: float | None = None
        self._options = options
        #: Where the robot was and how far it had to go at the last poll (shown while it runs).
        self.location: Pose2D | None = None
        self.left: float | None = None

    def options(self) -> GoalOptions | None:
        """The goal's options: those the node was made with (a service's retries), and the
        type's own."""
        return self._options

    def goal(self) -> tuple[str | None, Pose2D | None]:
        p = self.p
        assert isinstance(p, GoalParams)
        if p.point is not None:
            return p.point, None
        assert p.x is not None and p.y is not None
        return None, Pose2D(p.x, p.y, wrap_angle(p.theta))

    def begin(self, run: Run) -> None:
        point, pose = self.goal()
        assert isinstance(self.p, GoalParams)
        self._total = None
        self.attempt_id = run.robot.navigate(point=point, pose=pose, map_name=self.p.map,
                                             options=self.options())

    def refused(self, exc: PolynavError) -> NodeState:
        return NodeState.FAIL if isinstance(exc, NoRoute) else NodeState.ERROR

    def poll(self, run: Run) -> NodeState | None:
        assert self.attempt_id is not None
        outcome = run.robot.goal_outcome(self.attempt_id)
        if outcome is None:
            self._track(run)
            return None
        if outcome.end is GoalEnd.SUCCEEDED:
            pose = run.robot.pose()
            for key, value in zip(self.writes, (pose.x, pose.y, pose.theta), strict=True):
                run.blackboard.write(key, round(float(value), 4))
            return NodeState.COMPLETE
        if outcome.end is GoalEnd.CANCELED:
            run.taken = f"its goal was cancelled by another command ({self.type})"
            return NodeState.CANCELLED
        self.result = outcome.reason or "navigation failed"
        return NodeState.ERROR if outcome.reason in FAULTS else NodeState.FAIL

    def _track(self, run: Run) -> None:
        assert self.attempt_id is not None
        self.location = run.robot.pose()
        left = run.robot.distance_remaining(self.attempt_id)
        self.left = left
        if left is None:
            return
        if self._total is None or left > self._total:
            self._total = max(left, 1e-6)
        self.fraction = max(0.0, min(0.99, 1.0 - left / self._total))

    def live(self) -> dict[str, Any]:
        """The attempt, and while it runs the robot's pose (map frame) and the path length
        left [m] at the last poll (``None`` when not known)."""
        where = None
        if self.state.active and self.location is not None:
            where = {"x": float(self.location.x), "y": float(self.location.y),
                     "theta": float(self.location.theta)}
        return {"attempt_id": self.attempt_id, "location": where,
                "distance_left": self.left if self.state.active else None}

    def hold(self, run: Run) -> None:
        if self.attempt_id is not None:
            run.robot.pause_goal(self.attempt_id)

    def carry_on(self, run: Run) -> None:
        if self.attempt_id is None:
            return
        outcome = run.robot.goal_outcome(self.attempt_id)
        if outcome is None:
            run.robot.resume_goal(self.attempt_id)
            return
        if outcome.end is not GoalEnd.CANCELED:
            return  # it ended on its own just before the pause: poll takes it
        # Cancelled while paused (a detour to the charger drove elsewhere): go again.
        try:
            self.begin(run)
        except PolynavError as exc:
            self.end(run, self.refused(exc), str(exc))

    def halt(self, run: Run) -> None:
        if self.attempt_id is not None:
            run.robot.cancel_goal(self.attempt_id)

    def reset(self) -> None:
        super().reset()
        self.attempt_id = None
        self.location = None
        self.left = None


@action_type
class NavAction(_Goal):
    """Go to a pose or a named point (on another map: across the site)."""

    type = "nav_action"


class PassParams(GoalParams):
    radius: float = Field(gt=0.0, le=100.0)


@action_type
class NoneStopNavAction(_Goal):
    """Head for (x, y) and end as soon as the robot is within ``radius`` of it, without
    stopping: the next goal follows on (§5.3 #14)."""

    type = "none_stop_nav_action"
    schema = PassParams

    def options(self) -> GoalOptions:
        assert isinstance(self.p, PassParams)
        return replace(self._options or GoalOptions(), pass_tolerance=self.p.radius)


@action_type
class ChargeAction(_Goal):
    """Dock onto the charger at the pose (or point) and end once charging (§5.3 #6): a
    charger point of the map is docked onto; a pose names the charger's pile."""

    type = "charge_action"

    def options(self) -> GoalOptions:
        return replace(self._options or GoalOptions(), dock=True)


class SwitchParams(Params):
    map: str = Field(min_length=1)
    point: str | None = Field(default=None, min_length=1)


@action_type
class SwitchMapAction(Action):
    """Start navigation on ``map`` from ``point`` (the robot stands there: a direct
    connection's two ends are one place); done once the map is loaded and localized."""

    type = "switch_map_action"
    schema = SwitchParams

    def begin(self, run: Run) -> None:
        assert isinstance(self.p, SwitchParams)
        run.robot.switch_map(self.p.map, self.p.point)

    def poll(self, run: Run) -> NodeState | None:
        assert isinstance(self.p, SwitchParams)
        ready = run.robot.navigation_ready(self.p.map)
        if ready is None:
            return None
        if ready:
            return NodeState.COMPLETE
        self.result = f"navigation on {self.p.map} did not start"
        return NodeState.ERROR
