"""The robot's driven axes: ``slide_action``, ``jacking_action`` and ``jacking_rotate_action``
(galileo-tasks-bt-ws §5.3 #20-#22).

``mode`` is the vendors' axis mode: 0 jog (``speed`` for ``time`` seconds; ``speed`` may be
negative), 1 position (``pose`` [m] from zero, 0 meaning "stay"; ``angle`` [rad] for the
turntable, in the robot's frame or, with ``frame_id`` ``map``, the map's), 2 homing (find the
zero point), 3 percentage (``pose`` in 0..1 of the travel; the turntable has none). ``speed``
0 is the axis's default. The action is done when the move ends (``COMPLETE``); a device fault
during it is ``ERROR`` (the tree stops: a broken axis is not a goal to branch round); a move
stopped or replaced by another command ends ``FAIL``. Pausing stops the axis and resuming
moves it on (a jog for the time it had left); cancelling stops it where it is.

Limits the document leaves to the device (the travel) are the runtime's: a position beyond
the travel is refused when the action starts (``ERROR``), with the travel in the reason.

Blackboard, once the move ended: ``slide.position``, ``jacking.position`` [m],
``jacking.angle`` [rad, the turntable's frame].
"""

from __future__ import annotations

import builtins
from typing import Any, ClassVar, Literal

from pydantic import Field, model_validator

from polynav.geometry import wrap_angle
from polynav.robot.devices import AxisMode, JobState
from polynav.tasks.action import Action, Params, action_type
from polynav.tasks.node import Run
from polynav.tasks.states import NodeState

MIN_JOG_TIME = 0.1  # [s]
MIN_HOMING_SPEED = 0.05  # [m/s or rad/s] when not 0 (the default)


class AxisParams(Params):
    mode: Literal[0, 1, 2, 3]
    speed: float = 0.0
    time: float = Field(default=0.0, ge=0.0)
    pose: float = 0.0

    @model_validator(mode="after")
    def _by_mode(self) -> AxisParams:
        mode = AxisMode(self.mode)
        if mode is AxisMode.JOG and self.time < MIN_JOG_TIME:
            raise ValueError(f"a jog (mode 0) runs for time >= {MIN_JOG_TIME:g} s")
        if mode is not AxisMode.JOG and self.speed < 0.0:
            raise ValueError("speed: negative only in jog mode (0)")
        if mode is AxisMode.HOME and 0.0 < self.speed < MIN_HOMING_SPEED:
            raise ValueError(f"speed: homing (mode 2) at >= {MIN_HOMING_SPEED:g}, or 0")
        if mode is AxisMode.POSITION and self.pose < 0.0:
            raise ValueError("pose: a position (mode 1) is >= 0 from the zero point")
        if mode is AxisMode.RATIO and not 0.0 <= self.pose <= 1.0:
            raise ValueError("pose: a percentage (mode 3) is in 0..1")
        return self


class RotateParams(Params):
    mode: Literal[0, 1, 2]
    speed: float = 0.0
    time: float = Field(default=0.0, ge=0.0)
    angle: float = 0.0
    frame_id: Literal["map", "base_link"] = "base_link"

    @model_validator(mode="after")
    def _by_mode(self) -> RotateParams:
        mode = AxisMode(self.mode)
        if mode is AxisMode.JOG and self.time < MIN_JOG_TIME:
            raise ValueError(f"a jog (mode 0) runs for time >= {MIN_JOG_TIME:g} s")
        if mode is not AxisMode.JOG and self.speed < 0.0:
            raise ValueError("speed: negative only in jog mode (0)")
        if mode is AxisMode.HOME and 0.0 < self.speed < MIN_HOMING_SPEED:
            raise ValueError(f"speed: homing (mode 2) at >= {MIN_HOMING_SPEED:g}, or 0")
        return self


class _AxisMove(Action):
    """One move of one axis, followed through its device job."""

    axis: ClassVar[str] = ""
    schema: ClassVar[builtins.type[Params]] = AxisParams

    def __init__(self, params: dict[str, Any], **kwargs: Any) -> None:
        super().__init__(params, **kwargs)
        self.job_id: str | None = None
        self.jogged = 0.0  # [s] of a jog run before a pause
        self._since = 0.0

    def mode(self) -> AxisMode:
        p = self.p
        assert isinstance(p, AxisParams | RotateParams)
        return AxisMode(p.mode)

    def target(self, run: Run) -> float | None:
        """Where a position or percentage move goes; ``None``: stay where it is."""
        p = self.p
        assert isinstance(p, AxisParams)
        if self.mode() is AxisMode.POSITION and p.pose == 0.0:
            return None
        return p.pose

    def begin(self, run: Run) -> None:
        p = self.p
        assert isinstance(p, AxisParams | RotateParams)
        mode = self.mode()
        self._since = run.now
        if mode is AxisMode.JOG:
            self.job_id = run.robot.move_axis(self.axis, mode, speed=p.speed,
                                              duration=p.time - self.jogged)
            return
        target = self.target(run) if mode is not AxisMode.HOME else 0.0
        if target is None:
            self._write_position(run)
            self.end(run, NodeState.COMPLETE)
            return
        self.job_id = run.robot.move_axis(self.axis, mode, target=target, speed=p.speed)

    def poll(self, run: Run) -> NodeState | None:
        assert self.job_id is not None
        job = run.robot.axis_job(self.job_id)
        if job is None:
            self.result = f"{self.axis}: the move was lost"
            return NodeState.ERROR
        if job.state is JobState.WORKING:
            self.fraction = min(0.99, job.progress)
            return None
        if job.state is JobState.COMPLETE:
            self._write_position(run)
            return NodeState.COMPLETE
        if job.state is JobState.ERROR:
            self.result = f"{self.axis} fault: {job.reason or 'the device stopped'}"
            return NodeState.ERROR
        self.result = f"{self.axis}: the move was stopped by another command"
        return NodeState.FAIL

    def _write_position(self, run: Run) -> None:
        """Where the axis stands, under the type's one key."""
        run.blackboard.write(self.writes[0], round(run.robot.axis_position(self.axis), 4))

    def _stop(self, run: Run) -> None:
        if self.job_id is None:
            return
        job = run.robot.axis_job(self.job_id)
        if job is not None and job.state is JobState.WORKING:
            run.robot.stop_axis(self.axis)

    def halt(self, run: Run) -> None:
        self._stop(run)

    def hold(self, run: Run) -> None:
        self._stop(run)
        if self.mode() is AxisMode.JOG:
            self.jogged += run.now - self._since

    def carry_on(self, run: Run) -> None:
        self.begin(run)

    def reset(self) -> None:
        super().reset()
        self.job_id = None
        self.jogged = 0.0

    def live(self) -> dict[str, Any]:
        return {"job_id": self.job_id}


@action_type
class SlideAction(_AxisMove):
    """Move the slide table (linear stage)."""

    type = "slide_action"
    axis = "slide"
    writes = ("slide.position",)


@action_type
class JackingAction(_AxisMove):
    """Raise or lower the jacking lift."""

    type = "jacking_action"
    axis = "jacking"
    writes = ("jacking.position",)


@action_type
class JackingRotateAction(_AxisMove):
    """Turn the jacking turntable; ``angle`` [rad] in ``frame_id`` (``map``: the map's frame,
    the robot's heading taken off when the action starts)."""

    type = "jacking_rotate_action"
    axis = "jacking_rotation"
    writes = ("jacking.angle",)
    schema = RotateParams

    def target(self, run: Run) -> float | None:
        p = self.p
        assert isinstance(p, RotateParams)
        if p.frame_id == "map":
            return wrap_angle(p.angle - run.robot.pose().theta)
        return wrap_angle(p.angle)
