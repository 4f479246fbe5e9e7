"""Puwei tasks (``POST /api/task/set``, puwei-api §8.1) in the task engine's terms.

Pure: a Puwei task body becomes the engine's tree JSON (:mod:`polynav.tasks.tree`, Galileo's
form) and the schedules of :mod:`polynav.tasks.schedule`; the route module hands both to the
runtime. No clock, no store: the caller gives the calendar's now and the charger point.

Modes (docs/puwei.md, "Tasks"): 0 runs now; 1 ("timed", A28) runs once at the next occurrence
of each ``hour`` x ``minute``; 2 weekly on ``opt`` weekdays (Sunday = 0); 3 monthly on ``opt``
days 1-31, each at every ``hour`` x ``minute``. ``loop``: modes 0 and 1 run the actions
``loop`` times in a row per start (0: for ever); modes 2 and 3 run them once per start and
start ``loop`` times (0: for ever), as the schedules read Puwei's ``loop`` (docs/decisions.md,
"Task schedules").

Actions:

==  ================  =========================================================================
1   free points       ``nav_action`` {x, y, theta} per point ([m], [rad], puwei-api §8.1)
2   charge            ``true``: ``charge_action`` {point} to the map's charger; ``false``: none
3   trajectory        its poses in order (``reverse``: backwards), ``none_stop_nav_action``
                      {x, y, radius} through all but the last, ``nav_action`` onto the last
4   wait              ``angular`` 0: ``sleep_action`` {wait_time}; else a turn in place of
                      ``angular`` x ``time`` [rad] (``local_move_action`` {angle}, split in
                      turns of at most 2 pi)
5   topology station  ``nav_action`` {point} per station name (a point of the current map)
6   IO action         ``io_action`` {port: n, level: 1}: action n sets output n high (1-3)
==  ================  =========================================================================
"""

from __future__ import annotations

import datetime as dt
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from polynav.errors import InvalidRequest, NotFound
from polynav.protocols.puwei.request import type_name
from polynav.tasks.schedule import WEEKDAYS, puwei_weekday

IMMEDIATE, TIMED, WEEKLY, MONTHLY = 0, 1, 2, 3
FREE_POINTS, CHARGE, TRAJECTORY, WAIT, STATIONS, IO = 1, 2, 3, 4, 5, 6

#: How close a trajectory's intermediate poses are passed [m] (the robot does not stop there).
PASS_RADIUS = 0.3
#: The largest turn of one ``local_move_action`` [rad] (its own limit is 4 pi).
MAX_TURN = 2 * math.pi
#: IO outputs the simulated base has (``io_action`` ports).
IO_PORTS = (1, 2, 3)
#: At most this many actions and schedule times in one task.
MAX_ACTIONS = 1000
MAX_TIMES = 24 * 60


@dataclass(frozen=True, slots=True)
class PuweiTask:
    """A Puwei task, translated.

    Attributes:
        name: the task's name (the key ``/api/task/run/:name`` finds it by).
        mode: 0-3.
        tree: the engine's tree JSON.
        schedules: the schedule specs (:meth:`ScheduleSpec.from_json`), none for mode 0.
        stations: the topology station names used (points the current map must have).
    """

    name: str
    mode: int
    tree: dict[str, Any]
    schedules: list[dict[str, Any]] = field(default_factory=list)
    stations: list[str] = field(default_factory=list)


def _int(value: object, key: str, low: int, high: int | None = None) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise InvalidRequest(key, f"must be an integer, got {type_name(value)}")
    if value < low or (high is not None and value > high):
        bound = f"{low} to {high}" if high is not None else f">= {low}"
        raise InvalidRequest(key, f"must be {bound}, got {value}")
    return value


def _ints(value: object, key: str, low: int, high: int) -> list[int]:
    if not isinstance(value, list) or not value:
        raise InvalidRequest(key, f"must be a non-empty array of integers, got "
                                  f"{type_name(value)}")
    if len(value) > MAX_TIMES:
        raise InvalidRequest(key, f"at most {MAX_TIMES} values")
    return sorted({_int(v, f"{key}[{i}]", low, high) for i, v in enumerate(value)})


def _null(body: Mapping[str, Any], key: str, mode: int) -> None:
    if body.get(key) not in (None, []):
        raise InvalidRequest(key, f"must be null for mode {mode}")


def _pose(value: object, key: str) -> tuple[float, float, float]:
    if not isinstance(value, list) or len(value) != 3:
        raise InvalidRequest(key, "must be [x, y, theta] ([m], [m], [rad])")
    out: list[float] = []
    for i, v in enumerate(value):
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise InvalidRequest(f"{key}[{i}]", f"must be a finite number, got {type_name(v)}")
        out.append(float(v))
    return out[0], out[1], out[2]


def times_of_day(hours: list[int], minutes: list[int]) -> list[str]:
    """Every hour with every minute, ``"HH:MM"`` (A28: the product of the two lists)."""
    return [f"{h:02d}:{m:02d}" for h in hours for m in minutes]


def next_at(time_of_day: str, now: dt.datetime) -> dt.datetime:
    """The first ``time_of_day`` strictly after ``now`` (today, else tomorrow)."""
    hour, minute = (int(p) for p in time_of_day.split(":"))
    when = now.replace(hour=hour, minute=minute, second=0, microsecond=0)
    return when if when > now else when + dt.timedelta(days=1)


def actions_to_nodes(actions: object, *, charger: str | None) -> tuple[list[dict[str, Any]],
                                                                      list[str]]:
    """The engine's action nodes for Puwei's ``actions``, and the station names they use.

    Raises:
        InvalidRequest: a malformed action (the field named, ``actions[i].value...``).
        NotFound: a charge action with no charger point on the map.
    """
    if not isinstance(actions, list) or not actions:
        raise InvalidRequest("actions", f"must be a non-empty array, got {type_name(actions)}")
    if len(actions) > MAX_ACTIONS:
        raise InvalidRequest("actions", f"at most {MAX_ACTIONS} actions")
    nodes: list[dict[str, Any]] = []
    stations: list[str] = []
    for i, action in enumerate(actions):
        where = f"actions[{i}]"
        if not isinstance(action, dict):
            raise InvalidRequest(where, f"must be an object, got {type_name(action)}")
        kind = _int(action.get("type"), f"{where}.type", 1, 6)
        if "value" not in action:
            raise InvalidRequest(f"{where}.value", "is required")
        value = action["value"]
        key = f"{where}.value"
        if kind == FREE_POINTS:
            nodes.extend(_free_points(value, key))
        elif kind == CHARGE:
            if not isinstance(value, bool):
                raise InvalidRequest(key, f"must be true or false, got {type_name(value)}")
            if value:
                if charger is None:
                    raise NotFound("charger point on the current map", "charge")
                nodes.append({"type": "charge_action", "name": "charge", "point": charger})
        elif kind == TRAJECTORY:
            nodes.extend(_trajectory(value, key))
        elif kind == WAIT:
            nodes.extend(_wait(value, key))
        elif kind == STATIONS:
            names = _stations(value, key)
            stations.extend(names)
            nodes.extend({"type": "nav_action", "name": n, "point": n} for n in names)
        else:
            port = _int(value, key, 1)
            if port not in IO_PORTS:
                raise InvalidRequest(key, f"IO action {port}: the robot has outputs "
                                          f"{IO_PORTS[0]}-{IO_PORTS[-1]}")
            nodes.append({"type": "io_action", "name": f"io {port}", "port": port, "level": 1})
    if not nodes:
        raise InvalidRequest("actions", "nothing to do (only charge actions set to false)")
    return nodes, stations


def _free_points(value: object, key: str) -> list[dict[str, Any]]:
    if not isinstance(value, list) or not value:
        raise InvalidRequest(key, "must be a non-empty array of {name: [x, y, theta]}")
    nodes = []
    for j, item in enumerate(value):
        if not isinstance(item, dict) or len(item) != 1:
            raise InvalidRequest(f"{key}[{j}]", "must be one {name: [x, y, theta]}")
        ((name, pose),) = item.items()
        x, y, theta = _pose(pose, f"{key}[{j}].{name}")
        nodes.append({"type": "nav_action", "name": str(name), "x": x, "y": y, "theta": theta})
    return nodes


def _trajectory(value: object, key: str) -> list[dict[str, Any]]:
    if not isinstance(value, dict):
        raise InvalidRequest(key, f"must be {{reverse, name, points}}, got {type_name(value)}")
    reverse = value.get("reverse", False)
    if not isinstance(reverse, bool):
        raise InvalidRequest(f"{key}.reverse", f"must be true or false, got {type_name(reverse)}")
    name = value.get("name", "")
    if not isinstance(name, str):
        raise InvalidRequest(f"{key}.name", f"must be a string, got {type_name(name)}")
    points = value.get("points")
    if not isinstance(points, list) or not points:
        raise InvalidRequest(f"{key}.points", "must be a non-empty array of [x, y, theta]")
    poses = [_pose(p, f"{key}.points[{j}]") for j, p in enumerate(points)]
    if reverse:
        poses.reverse()
    nodes: list[dict[str, Any]] = [
        {"type": "none_stop_nav_action", "name": f"{name} {j}", "x": x, "y": y,
         "radius": PASS_RADIUS}
        for j, (x, y, _) in enumerate(poses[:-1])
    ]
    x, y, theta = poses[-1]
    nodes.append({"type": "nav_action", "name": f"{name} {len(poses) - 1}", "x": x, "y": y,
                  "theta": theta})
    return nodes


def _wait(value: object, key: str) -> list[dict[str, Any]]:
    if not isinstance(value, dict):
        raise InvalidRequest(key, f"must be {{time, angular}}, got {type_name(value)}")
    numbers: dict[str, float] = {}
    for name in ("time", "angular"):
        v = value.get(name, 0)
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise InvalidRequest(f"{key}.{name}", f"must be a finite number, got {type_name(v)}")
        numbers[name] = float(v)
    wait, angular = numbers["time"], numbers["angular"]
    if not 0.0 <= wait <= 86_400.0:
        raise InvalidRequest(f"{key}.time", f"must be 0 to 86400 s, got {wait:g}")
    if abs(angular) > 1.0:
        raise InvalidRequest(f"{key}.angular", f"must be -1 to 1 rad/s, got {angular:g}")
    if angular == 0.0:
        return [{"type": "sleep_action", "name": "wait", "wait_time": wait}]
    turn = angular * wait
    nodes = []
    while abs(turn) > 1e-9:
        step = math.copysign(min(abs(turn), MAX_TURN), turn)
        nodes.append({"type": "local_move_action", "name": "turn", "angle": step,
                      "distance": 0.0})
        turn -= step
    return nodes or [{"type": "sleep_action", "name": "wait", "wait_time": wait}]


def _stations(value: object, key: str) -> list[str]:
    if not isinstance(value, list) or not value:
        raise InvalidRequest(key, "must be a non-empty array of station names")
    names = []
    for j, name in enumerate(value):
        if not isinstance(name, str) or not name.strip():
            raise InvalidRequest(f"{key}[{j}]", f"must be a station name, got {type_name(name)}")
        names.append(name)
    return names


def parse_task(body: Mapping[str, Any], *, charger: str | None, now: dt.datetime
               ) -> PuweiTask:
    """Translate a ``task/set`` body (module docstring).

    Args:
        body: the JSON body.
        charger: the charger point of the current map, if it has one.
        now: the robot's calendar now (a timed task runs at the next occurrence after it).

    Raises:
        InvalidRequest: a missing or mistyped field, a value out of range.
        NotFound: a charge action without a charger point.
    """
    name = body.get("name")
    if not isinstance(name, str) or not name.strip():
        raise InvalidRequest("name", f"must be a non-empty string, got {type_name(name)}")
    if len(name) > 128:
        raise InvalidRequest("name", "at most 128 characters")
    mode = _int(body.get("mode"), "mode", 0, 3)
    loop = _int(body.get("loop"), "loop", 0)
    nodes, stations = actions_to_nodes(body.get("actions"), charger=charger)
    schedules: list[dict[str, Any]] = []
    if mode == IMMEDIATE:
        for key in ("minute", "hour", "opt"):
            _null(body, key, mode)
    else:
        times = times_of_day(_ints(body.get("hour"), "hour", 0, 23),
                             _ints(body.get("minute"), "minute", 0, 59))
        if mode == TIMED:
            _null(body, "opt", mode)
            schedules = [{"mode": "once", "at": next_at(t, now).isoformat(timespec="seconds")}
                         for t in times]
        elif mode == WEEKLY:
            days = _ints(body.get("opt"), "opt", 0, 6)
            schedules = [{"mode": "weekly", "times": times,
                          "weekdays": [WEEKDAYS[puwei_weekday(d)] for d in days], "loop": loop}]
        else:
            days = _ints(body.get("opt"), "opt", 1, 31)
            schedules = [{"mode": "monthly", "times": times, "days": days, "loop": loop}]
    if mode in (IMMEDIATE, TIMED):
        tree = {"control_type": "loop", "name": name, "target_loop_count": loop,
                "sub_tasks": nodes}
    else:
        tree = {"control_type": "sequence", "name": name, "sub_tasks": nodes}
    return PuweiTask(name, mode, tree, schedules, stations)
