"""The robot's state in Puwei's terms: the ``state`` code, ``err`` strings and the status body.

The source names a system status code (``state``) and "type code-sub code" error strings
(``err``) in O_STATUS but leaves their tables out (puwei-api A17). polynav's tables are in
docs/puwei.md ("State codes", "Error codes"); this module is their one implementation, for
``GET /api/robot/status`` and the WebSocket's O_STATUS alike, so both always agree. The one
example the source gives, ``state: 1`` with ``msg: "正在执行任务"``, is kept: 1 is a running task.

Everything here is a pure function of the status snapshot (plus the low-battery threshold and
the failure a client cleared), so it reads no clock and can be tested without a runtime.
"""

from __future__ import annotations

import enum
import math
from typing import Any

from polynav.geometry import yaw_to_quaternion
from polynav.runtime.status import StatusSnapshot


class State(enum.IntEnum):
    """``state`` (docs/puwei.md, "State codes"), in order of precedence: the first that holds
    is reported."""

    IDLE = 0
    RUNNING = 1
    PAUSED = 2
    CHARGING = 3
    MAPPING = 4
    LOADING = 5
    ERROR = 6


#: ``msg`` for each state, in the vendor's language (its example: "正在执行任务").
STATE_TEXT: dict[State, str] = {
    State.IDLE: "空闲",
    State.RUNNING: "正在执行任务",
    State.PAUSED: "任务已暂停",
    State.CHARGING: "正在充电",
    State.MAPPING: "正在建图",
    State.LOADING: "正在加载地图",
    State.ERROR: "故障",
}

#: Error types (the "type code" of "type-sub").
CHASSIS, LOCALIZATION, BATTERY, NAVIGATION = 1, 2, 3, 4

#: Navigation failure reasons to sub codes (type 4); an unknown reason is 99.
FAILURE_SUB: dict[str, int] = {
    "no path": 1,
    "goal occupied": 2,
    "stuck": 3,
    "localization lost": 4,
    "e-stop": 5,
    "undock failed": 6,
    "dock failed": 7,
    "blocked by person": 8,
    "not localized": 9,
}
OTHER_FAILURE = 99


def err_codes(snap: StatusSnapshot, *, low_battery_percent: float,
              cleared_attempt: int | None = None) -> list[str]:
    """The ``err`` list: every condition that holds now, as ``"type-sub"`` strings.

    Args:
        snap: the status snapshot.
        low_battery_percent: the ``low_bat`` threshold [%].
        cleared_attempt: the failed attempt a client acknowledged with ``/api/robot/clear``
            (its failure is no longer reported).
    """
    codes: list[str] = []
    if snap.estop_hardware:
        codes.append(f"{CHASSIS}-1")
    if snap.estop_software:
        codes.append(f"{CHASSIS}-2")
    if snap.mode == "navigating" and snap.localization_state == "lost":
        codes.append(f"{LOCALIZATION}-1")
    if snap.mode == "navigating" and snap.localization_state == "uninitialized":
        codes.append(f"{LOCALIZATION}-2")
    if not snap.charging and snap.battery_percent < low_battery_percent:
        codes.append(f"{BATTERY}-1")
    if snap.navigation_state == "failed" and snap.attempt_id != cleared_attempt:
        sub = FAILURE_SUB.get(snap.reason or "", OTHER_FAILURE)
        codes.append(f"{NAVIGATION}-{sub}")
    return codes


def state_of(snap: StatusSnapshot, *, task_running: bool, task_paused: bool) -> State:
    """The ``state`` code (precedence: :class:`State`'s docstring, docs/puwei.md)."""
    if snap.estop_hardware or snap.estop_software or (
            snap.mode == "navigating" and snap.localization_state == "lost"):
        return State.ERROR
    if snap.mode == "mapping":
        return State.MAPPING
    if snap.mode == "busy":
        return State.LOADING
    if task_paused or snap.navigation_state == "paused":
        return State.PAUSED
    if task_running or snap.navigation_state == "running":
        return State.RUNNING
    if snap.charging:
        return State.CHARGING
    return State.IDLE


def pose_body(x: float, y: float, theta: float) -> dict[str, Any]:
    """A ROS ``geometry_msgs/Pose`` as Puwei writes it (position [m], quaternion)."""
    qx, qy, qz, qw = yaw_to_quaternion(theta)
    return {"position": {"x": float(x), "y": float(y), "z": 0.0},
            "orientation": {"x": qx, "y": qy, "z": qz, "w": qw}}


def status_body(snap: StatusSnapshot, *, state: State, err: list[str], voltage: float,
                current: float, time_stamp_ms: int) -> dict[str, Any]:
    """The O_STATUS ``data`` fields (puwei-api §9.5, with ``voltage`` inside ``data``, A18)."""
    return {
        "current": float(current) if snap.charging else 0.0,
        "percentage": int(round(snap.battery_percent)),
        "pose": pose_body(snap.pose.x, snap.pose.y, snap.pose.theta),
        "twist": {"linear": {"x": float(snap.linear), "y": 0.0, "z": 0.0},
                  "angular": {"x": 0.0, "y": 0.0, "z": float(snap.angular)}},
        "voltage": float(voltage) if math.isfinite(voltage) else 0.0,
        "state": int(state),
        "err": err,
        "msg": STATE_TEXT[state],
        "time_stamp": time_stamp_ms,
        # 1 as in the source's example (a robot at work); 2 while an e-stop holds it.
        "chassis_mode": 2 if snap.estop_hardware or snap.estop_software else 1,
    }
