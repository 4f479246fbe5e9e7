"""Slide table and jacking mechanism (galileo-http-a §3.15, §3.16: E-64–E-69).

The axes move on the runtime's clock (:mod:`polynav.robot.sim.devices.axis`); a move returns
the task object at top level (A-19) with one action, whose state the task follows. ``pose`` is
a ratio of the travel in 0..1 (A-18; a value in (1, 100] is taken as a percentage); ``speed``
is optional on both, ``0`` meaning the default. An axis that has not found its zero point
homes first. ``zero_status`` is ``1`` once homed, ``0`` before, ``-1`` after a fault;
``current_pose`` and ``pose_ratio`` read ``0`` until homed. The jacking angle is in the robot
frame (``base_link``) unless ``frame_id=map`` asks for the map frame (the robot's heading
added); a target angle is in the robot frame (A-31).
"""

from __future__ import annotations

from typing import Any

from polynav.errors import InvalidRequest
from polynav.geometry import wrap_angle
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.endpoint import Reply, RouteList
from polynav.protocols.galileo.params import Params
from polynav.protocols.galileo.system_tasks import task_object, tasks
from polynav.robot.devices import AxisMode, AxisState

ROUTES = RouteList()

FRAMES = ("base_link", "map")


def _zero_status(state: AxisState) -> int:
    return -1 if state.fault else (1 if state.homed else 0)


def _pose(ctx: Context, axis: str) -> dict[str, Any]:
    state = ctx.runtime.peripherals.axis_state(axis)
    return {"zero_status": _zero_status(state), "current_pose": float(state.position),
            "pose_ratio": float(state.ratio)}


def _ratio(params: Params) -> float:
    pose = float(params.number("pose"))
    if 1.0 < pose <= 100.0:
        pose /= 100.0  # a percentage
    if not 0.0 <= pose <= 1.0:
        raise InvalidRequest("pose", f"must be a ratio in 0..1, got {pose:g}")
    return pose


def _speed(params: Params) -> float:
    speed = float(params.number("speed", 0.0))
    if speed < 0.0:
        raise InvalidRequest("speed", f"must be >= 0 (0: the default), got {speed:g}")
    return speed


def _move(ctx: Context, axis: str, name: str, action: str, mode: AxisMode, target: float,
          speed: float) -> Reply:
    peripherals = ctx.runtime.peripherals
    job = peripherals.move_axis(axis, mode, target=target, speed=speed)
    task = tasks(ctx).add(
        name,
        {"type": action, "mode": int(mode), "pose": target, "speed": speed, "time": 0},
        lambda: peripherals.job(job.job_id),
        lambda: peripherals.stop_axis(axis),
    )
    return task_object(task)


@ROUTES.get("/system/slide_pose")
def get_slide_pose(ctx: Context, params: Params) -> Reply:
    """E-64."""
    return _pose(ctx, "slide")


@ROUTES.get("/system/slide_move_to")
def get_slide_move_to(ctx: Context, params: Params) -> Reply:
    """E-65: a ``slide_task``."""
    return _move(ctx, "slide", "slide_task", "slide_action", AxisMode.RATIO, _ratio(params),
                 _speed(params))


@ROUTES.get("/system/jacking_pose")
def get_jacking_pose(ctx: Context, params: Params) -> Reply:
    """E-66."""
    return _pose(ctx, "jacking")


@ROUTES.get("/system/jacking_move_to")
def get_jacking_move_to(ctx: Context, params: Params) -> Reply:
    """E-67: a ``jacking_task``."""
    return _move(ctx, "jacking", "jacking_task", "jacking_action", AxisMode.RATIO,
                 _ratio(params), _speed(params))


@ROUTES.get("/system/jacking_angle")
def get_jacking_angle(ctx: Context, params: Params) -> Reply:
    """E-68: ``zero_status`` and ``current_angle`` [rad]."""
    frame = params.text("frame_id", "base_link")
    if frame not in FRAMES:
        raise InvalidRequest("frame_id", f"must be one of {', '.join(FRAMES)}, got {frame!r}")
    state = ctx.runtime.peripherals.axis_state("jacking_rotation")
    angle = float(state.position)
    if frame == "map" and state.homed:
        angle = wrap_angle(angle + ctx.runtime.status().pose.theta)
    return {"zero_status": _zero_status(state), "current_angle": angle}


@ROUTES.get("/system/jacking_angle_move_to")
def get_jacking_angle_move_to(ctx: Context, params: Params) -> Reply:
    """E-69: a ``jacking_task`` turning to ``angle`` [rad, robot frame]."""
    angle = wrap_angle(float(params.number("angle")))
    return _move(ctx, "jacking_rotation", "jacking_task", "jacking_rotate_action",
                 AxisMode.POSITION, angle, _speed(params))
