"""Puwei WebSocket messages (puwei-api §9): the envelope, the message types, the event table,
and the pure translations both ways.

Every frame is ``{"type": int, "data": ...}``. Client messages are checked whole here
(:func:`parse`) before anything is asked of the robot; a message that is not valid raises
:class:`~polynav.errors.InvalidRequest` naming the field, which the session answers with an
O_EVENT 1029 (EVENT_WARN_INVALID_CMD) to that client alone, the session staying open.
Runtime events become O_EVENT frames (:func:`events_for`) with the document's event ids and
texts in the vendor's language; two texts are matched by real clients and are kept exactly:
task start "开始执行任务" and task completion "完成任务".
"""

from __future__ import annotations

import base64
import enum
import json
import math
from dataclasses import dataclass
from typing import Any

from polynav.errors import InvalidRequest
from polynav.geometry import Pose2D, quaternion_to_yaw, yaw_to_quaternion
from polynav.runtime import events

MAX_FRAME = 1 << 20  # [bytes] of one client frame
MAX_GOALS = 200
MAX_MARKERS = 500
MAX_SPEED = 1.0  # I_CMD: ±1 m/s, ±1 rad/s (L434-L438)


class In(enum.IntEnum):
    """Client -> server message types (L339-L351)."""

    I_NONE = 0
    I_INIT = 1
    I_GOAL = 2
    I_PAUSE = 3
    I_CMD = 4
    I_CHARGE = 5
    I_CLEAR = 6
    I_ALARM = 7
    I_MARKER = 8


class Out(enum.IntEnum):
    """Server -> client message types (L352-L360)."""

    O_MAP = 1024
    O_PATH = 1025
    O_STATUS = 1026
    O_GOAL = 1027
    O_EVENT = 1028
    O_MARKER = 1029


#: O_EVENT ids and their texts (L678-L719).
EVENT_TEXT: dict[int, str] = {
    0: "启动成功", 1: "重定位成功", 2: "正在进行重定位", 3: "完成任务", 4: "任务取消",
    5: "任务暂停", 6: "开始执行任务", 7: "开始充电对接", 8: "正在退出充电", 9: "保存marker点成功",
    10: "接收任务", 11: "充电对接成功", 12: "清除所有错误", 13: "到达目标点", 14: "退出充电成功",
    15: "取消对接/退出充电桩", 16: "充电达到阈值", 17: "检测到充电桩", 18: "开始录制轨迹",
    19: "结束录制轨迹",
    1025: "重定位失败", 1026: "规划失败", 1027: "保存marker失败", 1028: "定位丢失",
    1029: "输入的命令无效", 1030: "底盘出现错误", 1031: "传感器出现错误", 1032: "未检测到充电桩",
    1033: "录制的轨迹达到上限",
    2048: "程序退出", 2049: "任务失败", 2050: "充电过程中出现错误", 2051: "退出充电桩失败",
    2052: "对接充电桩失败",
}

START, RELOC_OK, RELOCATING, TASK_DONE, TASK_CANCELLED, TASK_PAUSED, TASK_STARTED = range(7)
DOCKING, LEAVING, MARKER_SAVED, GOALS_RECEIVED, DOCKED, CLEARED, REACHED = 7, 8, 9, 10, 11, 12, 13
LEFT_CHARGER, CHARGE_CANCELLED, CHARGE_FULL = 14, 15, 16
RELOC_FAILED, PLAN_FAILED, MARKER_FAILED, LOST, INVALID = 1025, 1026, 1027, 1028, 1029
CHASSIS_ERROR = 1030
PROGRAM_EXIT, TASK_FAILED, LEAVE_FAILED, DOCK_FAILED = 2048, 2049, 2051, 2052


def frame(kind: Out, data: Any) -> str:
    """One server frame as JSON text."""
    return json.dumps({"type": int(kind), "data": data}, ensure_ascii=False,
                      allow_nan=False)


def event(code: int, detail: str = "") -> str:
    """An O_EVENT frame: the document's text, with ``detail`` after it when there is one."""
    text = EVENT_TEXT[code] + (f": {detail}" if detail else "")
    return frame(Out.O_EVENT, {"code": code, "msg": text})


# -- client messages ---------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Message:
    """A checked client message: its type and its data in polynav's terms."""

    kind: In
    data: Any


def _number(value: object, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise InvalidRequest(where, f"must be a finite number, got {value!r}")
    return float(value)


def _object(value: object, where: str) -> dict[str, Any]:
    if not isinstance(value, dict):
        raise InvalidRequest(where, "must be an object")
    return value


def pose_of(value: object, where: str) -> Pose2D:
    """A ROS pose (``position``, quaternion ``orientation``) as a map pose."""
    body = _object(value, where)
    position = _object(body.get("position"), f"{where}.position")
    orientation = _object(body.get("orientation"), f"{where}.orientation")
    x = _number(position.get("x"), f"{where}.position.x")
    y = _number(position.get("y"), f"{where}.position.y")
    q = [_number(orientation.get(k), f"{where}.orientation.{k}") for k in "xyzw"]
    if math.hypot(*q) < 1e-6:
        raise InvalidRequest(f"{where}.orientation", "a quaternion of length 0")
    return Pose2D(x, y, quaternion_to_yaw(*q))


def _flag(value: object, where: str) -> bool:
    if not isinstance(value, bool):
        raise InvalidRequest(where, f"must be true or false, got {value!r}")
    return value


def parse(text: str | bytes) -> Message:
    """A client frame, checked whole.

    Raises:
        InvalidRequest: not JSON, not an envelope, an unknown or reserved type, a field
            missing, of the wrong type or out of range.
    """
    if len(text) > MAX_FRAME:
        raise InvalidRequest("frame", f"larger than {MAX_FRAME} bytes")
    try:
        body = json.loads(text)
    except ValueError as exc:
        raise InvalidRequest("frame", f"not JSON: {exc}") from None
    if not isinstance(body, dict) or "type" not in body:
        raise InvalidRequest("frame", 'must be {"type": int, "data": ...}')
    raw = body["type"]
    if isinstance(raw, bool) or not isinstance(raw, int) or raw not in In._value2member_map_:
        raise InvalidRequest("type", f"unknown message type {raw!r}")
    kind = In(raw)
    data = body.get("data")
    if kind is In.I_NONE:
        raise InvalidRequest("type", "0 (I_NONE) is reserved")
    if kind is In.I_INIT:
        return Message(kind, pose_of(data, "data"))
    if kind is In.I_GOAL:
        goal = _object(data, "data")
        poses = goal.get("poses")
        if not isinstance(poses, list) or not 1 <= len(poses) <= MAX_GOALS:
            raise InvalidRequest("data.poses", f"must be a list of 1 to {MAX_GOALS} poses")
        loop = goal.get("loop", 1)
        if isinstance(loop, bool) or not isinstance(loop, int) or not 0 <= loop <= 100_000:
            raise InvalidRequest("data.loop", f"must be an integer >= 0 (0: for ever), got "
                                              f"{loop!r}")
        return Message(kind, (tuple(pose_of(p, f"data.poses[{i}]")
                                    for i, p in enumerate(poses)), loop))
    if kind in (In.I_PAUSE, In.I_CHARGE, In.I_ALARM):
        return Message(kind, _flag(data, "data"))
    if kind is In.I_CMD:
        cmd = _object(data, "data")
        linear = _number(cmd.get("linear"), "data.linear")
        angular = _number(cmd.get("angular"), "data.angular")
        for name, value in (("linear", linear), ("angular", angular)):
            if abs(value) > MAX_SPEED:
                raise InvalidRequest(f"data.{name}", f"must be within ±{MAX_SPEED:g}, got "
                                                     f"{value:g}")
        return Message(kind, (linear, angular))
    if kind is In.I_CLEAR:
        if data is not None:
            raise InvalidRequest("data", "must be null")
        return Message(kind, None)
    return Message(kind, markers_of(data))


def markers_of(value: object) -> tuple[tuple[str, Pose2D], ...]:
    """``[{name: [x, y, theta_degrees]}, ...]`` (A13: degrees) as named map poses."""
    if not isinstance(value, list) or not 1 <= len(value) <= MAX_MARKERS:
        raise InvalidRequest("data", f"must be a list of 1 to {MAX_MARKERS} markers")
    out: list[tuple[str, Pose2D]] = []
    for i, item in enumerate(value):
        if not isinstance(item, dict) or len(item) != 1:
            raise InvalidRequest(f"data[{i}]", "must be {name: [x, y, theta]}")
        (name, xyt), = item.items()
        if not isinstance(name, str) or not name.strip() or len(name) > 100:
            raise InvalidRequest(f"data[{i}]", "a marker needs a name")
        if not isinstance(xyt, list) or len(xyt) != 3:
            raise InvalidRequest(f"data[{i}].{name}", "must be [x, y, theta]")
        x, y, theta = (_number(v, f"data[{i}].{name}") for v in xyt)
        out.append((name, Pose2D(x, y, math.radians(theta))))
    return tuple(out)


# -- server messages ---------------------------------------------------------------------------


def pose_body(pose: Pose2D) -> dict[str, Any]:
    qx, qy, qz, qw = yaw_to_quaternion(pose.theta)
    return {"position": {"x": float(pose.x), "y": float(pose.y), "z": 0.0},
            "orientation": {"x": qx, "y": qy, "z": qz, "w": qw}}


def goal_data(poses: tuple[Pose2D, ...], loop: int) -> dict[str, Any]:
    """I_GOAL's and O_GOAL's ``data``."""
    return {"poses": [pose_body(p) for p in poses], "loop": loop}


def path_data(points: list[tuple[float, float]]) -> dict[str, Any]:
    """O_PATH's ``data``: nav_msgs/Path-like poses, each heading along the path (A16)."""
    poses = []
    for i, (x, y) in enumerate(points):
        nx, ny = points[min(i + 1, len(points) - 1)]
        px, py = points[max(i - 1, 0)]
        heading = math.atan2(ny - py, nx - px) if (nx, ny) != (px, py) else 0.0
        poses.append({"pose": pose_body(Pose2D(x, y, heading))})
    return {"poses": poses}


def map_data(png: bytes, resolution: float, width: int, height: int,
             origin: Pose2D) -> dict[str, Any]:
    """O_MAP's ``data``: a PNG data URL and where it lies (A14)."""
    return {"data": "data:image/png;base64," + base64.b64encode(png).decode("ascii"),
            "resolution": float(resolution), "width": int(width), "height": int(height),
            "origin": [float(origin.x), float(origin.y), float(origin.theta)]}


def marker_data(markers: list[tuple[str, Pose2D]]) -> list[dict[str, list[float]]]:
    """O_MARKER's ``data``: ``[{name: [x, y, theta_degrees]}]``."""
    return [{name: [round(p.x, 4), round(p.y, 4), round(math.degrees(p.theta), 3)]}
            for name, p in markers]


#: Root task states -> O_EVENT ids.
_TASK_EVENT = {"WORKING": TASK_STARTED, "COMPLETE": TASK_DONE, "CANCELLED": TASK_CANCELLED,
               "PAUSED": TASK_PAUSED, "FAIL": TASK_FAILED, "ERROR": TASK_FAILED}


def events_for(happened: events.RuntimeEvent, *, was_paused: bool = False) -> list[str]:
    """The O_EVENT frames for one runtime event (none for events Puwei has no id for).

    ``was_paused``: a task going back to WORKING was paused (resumed, not started again).
    """
    if isinstance(happened, events.TaskChanged):
        if not happened.root:
            return []
        code = _TASK_EVENT.get(happened.state)
        if code is None or (code == TASK_STARTED and was_paused):
            return []
        return [event(code, happened.result if code == TASK_FAILED else "")]
    simple: dict[type[events.RuntimeEvent], int] = {
        events.NavigationSucceeded: REACHED, events.PlanningFailed: PLAN_FAILED,
        events.DockingStarted: DOCKING, events.DockingSucceeded: DOCKED,
        events.DockingFailed: DOCK_FAILED, events.ChargerLeaveStarted: LEAVING,
        events.ChargerLeft: LEFT_CHARGER, events.ChargerLeaveFailed: LEAVE_FAILED,
    }
    code = simple.get(type(happened))
    if code is not None:
        return [event(code)]
    if isinstance(happened, events.ModeChanged) and happened.new in ("navigating", "mapping"):
        return [event(START)]
    if isinstance(happened, events.PoseInitialized):
        return [event(RELOCATING)]
    if isinstance(happened, events.LocalizationChanged):
        if happened.state == "tracking":
            return [event(RELOC_OK)]
        if happened.state == "lost":
            return [event(LOST)]
        return []
    if isinstance(happened, events.EStopChanged) and happened.active:
        return [event(CHASSIS_ERROR, "e-stop")]
    if isinstance(happened, events.AutoChargeEnded) and happened.charged:
        return [event(CHARGE_FULL)]
    # EVENT_ERROR_PROGRAM_EXIT (A23: by its name, not its copied comment): the robot's program
    # is about to stop, which a client learns before its socket drops.
    if isinstance(happened, events.SoftwareShutdownNotice):
        return [event(PROGRAM_EXIT, "shutdown")]
    if isinstance(happened, events.PowerOffNotice):
        return [event(PROGRAM_EXIT, f"{'reboot' if happened.reboot else 'power off'} in "
                                    f"{happened.after:g} s")]
    return []

