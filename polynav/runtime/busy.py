"""What the robot is in the middle of, for timers that must not cut into it.

A power-off or a scheduled task start fires from a timer on the loop, not at an operator's
request: it cannot ask anyone to stop mapping first, and a refusal raised inside the timer
would only reach the log with the power-off half done (issue 32). So those timers ask here
first and either wait, end the activity, or were refused when they were asked
(docs/decisions.md, "Timers never fail half-done"). Every function runs between ticks.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from polynav.runtime.config import Mode
from polynav.runtime.lift_events import LiftPhase

if TYPE_CHECKING:
    from polynav.runtime.robot_runtime import RobotRuntime

IN_CAR = frozenset({LiftPhase.ENTERING, LiftPhase.RIDING, LiftPhase.SWITCHING_MAP,
                    LiftPhase.EXITING})
"""Lift phases in which the robot is in the car or its door: it must not stop there."""


def in_lift_car(runtime: RobotRuntime) -> str | None:
    """The car the robot is entering, riding or leaving, if any."""
    run = runtime._route
    if run is not None and run.phase in IN_CAR:
        return run.car or "a lift"
    return None


def docking(runtime: RobotRuntime) -> bool:
    """Whether a goal is in its docking phase (driving onto the charger's contacts)."""
    snapshot = runtime.status()
    return snapshot.navigation_state == "running" and snapshot.phase == "dock"


def busy_reason(runtime: RobotRuntime) -> str | None:
    """Why a scheduled task must not start now, or ``None`` when the robot is free: off or
    shutting down, mapping, loading a map, riding a lift, docking, another task, a goal, a
    patrol or a local move that somebody started."""
    if not runtime.powered or runtime.device.power.shutting_down:
        return "the robot is shutting down"
    if runtime.mode is Mode.MAPPING:
        return "the robot is mapping"
    if runtime.mode is Mode.BUSY:
        return "the robot is loading a map"
    car = in_lift_car(runtime)
    if car is not None:
        return f"the robot is riding lift {car}"
    if docking(runtime):
        return "the robot is docking"
    task = runtime.tasks.engine.running
    if task is not None:
        return f"task {task.id} ({task.name!r}) is {task.state.value}"
    if runtime._goal_active() or runtime.local_move_active:
        return "the robot is on a goal"
    return None
