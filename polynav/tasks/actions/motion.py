"""Short exact moves: ``local_move_action`` and ``local_move_target_action`` (§5.3 #7, #23),
on the runtime's local moves (turn on the spot, drive straight; checked against obstacles)."""

from __future__ import annotations

import builtins
import math
from typing import Any, ClassVar, Literal

from pydantic import Field, field_validator

from polynav.geometry import Pose2D, wrap_angle
from polynav.tasks.action import Action, Params, action_type
from polynav.tasks.node import Run
from polynav.tasks.states import NodeState

MAX_DISTANCE = 20.0  # [m] of one local move


class MoveParams(Params):
    distance: float = Field(default=0.0, ge=-MAX_DISTANCE, le=MAX_DISTANCE)
    angle: float = Field(default=0.0, ge=-4 * math.pi, le=4 * math.pi)
    method: int = Field(default=0, ge=0, le=1)


@action_type
class LocalMoveAction(Action):
    """Turn by ``angle`` [rad], then drive ``distance`` [m] (negative: backwards)."""

    type = "local_move_action"
    schema: ClassVar[builtins.type[Params]] = MoveParams

    def __init__(self, params: dict[str, Any], **kwargs: Any) -> None:
        super().__init__(params, **kwargs)
        self.steps: list[tuple[str, float]] = []

    def planned_steps(self, run: Run) -> list[tuple[str, float]]:
        assert isinstance(self.p, MoveParams)
        return [(kind, value) for kind, value in (("rotate", self.p.angle),
                                                    ("distance", self.p.distance))
                if abs(value) > 1e-6]

    def begin(self, run: Run) -> None:
        self.steps = self.planned_steps(run)
        self._next(run)

    def _next(self, run: Run) -> bool:
        if not self.steps:
            return False
        kind, value = self.steps.pop(0)
        if kind == "rotate":
            run.robot.local_move(rotate=value)
        else:
            run.robot.local_move(distance=value)
        return True

    def poll(self, run: Run) -> NodeState | None:
        if run.robot.local_move_active():
            return None
        if self._next(run):
            return None
        return NodeState.COMPLETE

    def halt(self, run: Run) -> None:
        self.steps.clear()
        if run.robot.local_move_active():
            run.robot.stop_local_move()

    def hold(self, run: Run) -> None:
        # A local move is short: pausing stops it, resuming does the rest from where it is.
        self.halt(run)

    def carry_on(self, run: Run) -> None:
        self.begin(run)


class TargetParams(Params):
    x: float
    y: float
    theta: float = 0.0
    frame_id: Literal["map", "base_link"] = "map"
    xy_tolerance: float = Field(default=0.05, gt=0.0)
    yaw_tolerance: float = Field(default=0.05, gt=0.0)
    timeout: float = Field(default=60.0, ge=0.0)
    start_rotate_enable: bool = True
    target_rotate_enable: bool = True

    @field_validator("target_rotate_enable", "start_rotate_enable", mode="before")
    @classmethod
    def _number_as_bool(cls, value: object) -> object:
        """A-17: typed float in the document, meaning a bool (non-zero: true)."""
        if isinstance(value, int | float) and not isinstance(value, bool):
            return value != 0
        return value


@action_type
class LocalMoveTargetAction(LocalMoveAction):
    """Reach ``x, y, theta`` (frame ``map`` or ``base_link``) by local moves: turn towards
    it, drive straight, turn to ``theta``; steps within the tolerances are skipped; ``ERROR``
    ``timeout`` after ``timeout`` s (0: none)."""

    type = "local_move_target_action"
    schema = TargetParams

    def __init__(self, params: dict[str, Any], **kwargs: Any) -> None:
        super().__init__(params, **kwargs)
        self.deadline: float | None = None

    def target(self, pose: Pose2D) -> Pose2D:
        p = self.p
        assert isinstance(p, TargetParams)
        if p.frame_id == "base_link":
            c, s = math.cos(pose.theta), math.sin(pose.theta)
            return Pose2D(pose.x + c * p.x - s * p.y, pose.y + s * p.x + c * p.y,
                          wrap_angle(pose.theta + p.theta))
        return Pose2D(p.x, p.y, wrap_angle(p.theta))

    def planned_steps(self, run: Run) -> list[tuple[str, float]]:
        p = self.p
        assert isinstance(p, TargetParams)
        pose = run.robot.pose()
        goal = self.target(pose)
        steps: list[tuple[str, float]] = []
        dx, dy = goal.x - pose.x, goal.y - pose.y
        distance = math.hypot(dx, dy)
        heading = pose.theta
        if distance > p.xy_tolerance:
            bearing = math.atan2(dy, dx)
            turn = wrap_angle(bearing - pose.theta)
            if not p.start_rotate_enable:  # reverse rather than turn round
                steps.append(("distance", distance if math.cos(turn) >= 0.0 else -distance))
            else:
                if abs(turn) > p.yaw_tolerance:
                    steps.append(("rotate", turn))
                    heading = bearing
                steps.append(("distance", distance))
        final = wrap_angle(goal.theta - heading)
        if p.target_rotate_enable and abs(final) > p.yaw_tolerance:
            steps.append(("rotate", final))
        return steps

    def begin(self, run: Run) -> None:
        assert isinstance(self.p, TargetParams)
        if self.deadline is None and self.p.timeout > 0:
            self.deadline = run.now + self.p.timeout
        super().begin(run)

    def poll(self, run: Run) -> NodeState | None:
        if self.deadline is not None and run.now > self.deadline:
            self.halt(run)
            self.result = "timeout"
            return NodeState.FAIL
        return super().poll(run)

    def reset(self) -> None:
        super().reset()
        self.deadline = None
