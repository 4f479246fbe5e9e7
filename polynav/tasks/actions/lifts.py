"""Driving a lift car step by step: ``elevator_req_action`` (galileo-tasks-bt-ws §5.3 #13) and
the Robustel gateway's ``lbt_elevator_req_action`` and ``lbt_elevator_ack_action`` (#18, #19).

A tree that rides a lift itself (§7.5(a): call the car, drive in, ride, drive out) uses these
where a ``nav_action`` to another floor would let the runtime's lift sequence do it all. The
runtime holds the car for the task: it asks for the car's session (the lease robots of a
building share) and calls the car with its doors open (:meth:`~polynav.runtime.lift_access
.LiftAccess.hold_lift`); the car is given back by an acknowledgement, by cancelling the call,
or when the task ends, however it ends.

- ``elevator_req_action`` with ``direction`` (``up``/``down``, the hall button; the robot is
  outside): calls the car to the robot's floor. With ``level`` (the robot is inside): sends the
  car to that floor. ``COMPLETE`` when the car stands at the floor with its doors open (the
  document's rule). ``FAIL`` when the car is occupied (another robot or an operator holds it,
  or, called from outside, it arrives full), out of service, or has not come within
  ``timeout`` seconds: a branch for a fallback (wait, back off, call again), never ``ERROR``.
  A car that cannot be named (no such car, no floor at ``level``, no car stopping here) is
  ``ERROR``: bad parameters.
- ``lbt_elevator_req_action``: ``cmd`` ``enter`` calls the car to ``from_level`` (as
  ``direction``), ``leave`` waits for it at ``to_level`` (as ``level``); same ends.
- ``lbt_elevator_ack_action``: the enter or leave has finished. After an enter the car is sent
  on to ``to_level`` (the ride starts; the gateway's own order); otherwise the car is given
  back. It is also the tree's "cancel the lift request": with no enter pending it ends the
  robot's hold on any car, and nothing when none is held. Done at once.

Beside the documented parameters, ``lift`` names the car (default: the one held, else the
nearest car stopping on the robot's map that serves the floor) and ``timeout`` [s] bounds the
wait (default 180, the lift sequence's call timeout).

Blackboard: ``lift.car`` and ``lift.floor`` (where the car stands open), and for the gateway
``lbt.cmd`` (the request an acknowledgement finishes) and ``lbt.to_level``.
"""

from __future__ import annotations

from typing import Any, ClassVar, Literal

from pydantic import Field, model_validator

from polynav.errors import PolynavError
from polynav.robot.lift import LiftError
from polynav.tasks.action import Action, Params, action_type
from polynav.tasks.node import Run
from polynav.tasks.states import NodeState

CALL_TIMEOUT = 180.0  # [s] as the runtime's lift sequence waits for a car it called
MAX_WAIT = 3600.0  # [s]


class _CarParams(Params):
    lift: str | None = Field(default=None, min_length=1, max_length=128)
    timeout: float = Field(default=CALL_TIMEOUT, gt=0.0, le=MAX_WAIT)


class ElevatorParams(_CarParams):
    level: int | None = None
    direction: Literal["up", "down"] | None = None

    @model_validator(mode="after")
    def _inside_or_outside(self) -> ElevatorParams:
        if (self.level is None) == (self.direction is None):
            raise ValueError("give level (the robot is inside the car: the floor to go to) or "
                             "direction (it is outside: the hall button), not both")
        return self


class _LiftCall(Action):
    """Call a car to a floor and wait until it stands there open."""

    writes: ClassVar[tuple[str, ...]] = ("lift.car", "lift.floor")

    def __init__(self, params: dict[str, Any], **kwargs: Any) -> None:
        super().__init__(params, **kwargs)
        self.deadline = 0.0
        self.car: str | None = None

    def target(self, run: Run) -> tuple[int | None, bool]:
        """The level to call the car to (``None``: the robot's floor), and whether the robot
        waits outside (so it needs room in the car)."""
        raise NotImplementedError

    def refused(self, exc: PolynavError) -> NodeState:
        return NodeState.FAIL if isinstance(exc, LiftError) else NodeState.ERROR

    def begin(self, run: Run) -> None:
        p = self.p
        assert isinstance(p, _CarParams)
        level, _ = self.target(run)
        self.deadline = run.now + p.timeout
        self.car = run.robot.call_lift(car=p.lift, level=level, task_id=run.task_id).car

    def poll(self, run: Run) -> NodeState | None:
        call = run.robot.lift_call()
        if call is None or call.car != self.car:
            self.result = "the lift call was cancelled"
            return NodeState.FAIL
        if call.refused:
            return self._give_up(run, f"lift {call.car} refused the call: {call.refused}")
        if call.ready:
            _, outside = self.target(run)
            if outside and call.full:
                return self._give_up(run, f"lift {call.car} is full")
            run.blackboard.write("lift.car", call.car)
            run.blackboard.write("lift.floor", call.floor)
            return NodeState.COMPLETE
        if run.now > self.deadline:
            assert isinstance(self.p, _CarParams)
            return self._give_up(run, f"lift {call.car} did not come within "
                                      f"{self.p.timeout:g} s")
        return None

    def _give_up(self, run: Run, why: str) -> NodeState:
        """Give the car back (others may use it while this robot backs off) and fail."""
        run.robot.release_lift()
        self.result = why
        return NodeState.FAIL

    def halt(self, run: Run) -> None:
        call = run.robot.lift_call()
        if call is not None and call.car == self.car and not call.ready:
            run.robot.release_lift()  # the call is cancelled; a car standing open stays held

    def reset(self) -> None:
        super().reset()
        self.car = None

    def live(self) -> dict[str, Any]:
        return {"lift": self.car}


@action_type
class ElevatorReqAction(_LiftCall):
    """Call the car (``direction``: to the robot's floor) or ride it (``level``); done when it
    stands there with its doors open."""

    type = "elevator_req_action"
    schema = ElevatorParams

    def target(self, run: Run) -> tuple[int | None, bool]:
        p = self.p
        assert isinstance(p, ElevatorParams)
        return p.level, p.level is None


class LbtParams(_CarParams):
    from_level: int
    to_level: int
    cmd: Literal["enter", "leave"]


@action_type
class LbtElevatorReqAction(_LiftCall):
    """Ask for the car ready to ``enter`` at ``from_level`` or to ``leave`` at ``to_level``;
    done when it stands there with its doors open."""

    type = "lbt_elevator_req_action"
    schema = LbtParams
    writes = ("lift.car", "lift.floor", "lbt.cmd", "lbt.to_level")

    def target(self, run: Run) -> tuple[int | None, bool]:
        p = self.p
        assert isinstance(p, LbtParams)
        return (p.from_level, True) if p.cmd == "enter" else (p.to_level, False)

    def poll(self, run: Run) -> NodeState | None:
        state = super().poll(run)
        if state is NodeState.COMPLETE:
            p = self.p
            assert isinstance(p, LbtParams)
            run.blackboard.write("lbt.cmd", p.cmd)
            run.blackboard.write("lbt.to_level", p.to_level)
        return state


@action_type
class LbtElevatorAckAction(Action):
    """The enter or leave has finished: after an enter the car is sent on to ``to_level``,
    else the car is given back (see the module); done at once."""

    type = "lbt_elevator_ack_action"
    writes = ("lbt.cmd",)

    def refused(self, exc: PolynavError) -> NodeState:
        return NodeState.FAIL if isinstance(exc, LiftError) else NodeState.ERROR

    def begin(self, run: Run) -> None:
        pending, to_level = run.blackboard.read("lbt.cmd"), run.blackboard.read("lbt.to_level")
        held = run.robot.lift_call()
        if pending == "enter" and held is not None and isinstance(to_level, int):
            run.robot.call_lift(car=held.car, level=to_level, task_id=run.task_id)
            run.blackboard.write("lbt.cmd", "ride")
            self.end(run, NodeState.COMPLETE, f"lift {held.car} sent to level {to_level}")
            return
        run.robot.release_lift()
        run.blackboard.write("lbt.cmd", "")
        self.end(run, NodeState.COMPLETE,
                 f"lift {held.car} given back" if held is not None else "no lift was held")
