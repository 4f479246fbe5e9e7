"""The actions of Galileo task objects that the navigation endpoints create, each driving one
runtime command and telling when it has ended.

An action is started once (:meth:`Action.start`, between runtime ticks) and then polled on the
runtime's clock (:meth:`Action.poll`) until it returns a final state. Navigation actions end
with their attempt (its outcome arrives as a runtime event, see :class:`Outcomes`); a sleep
ends on the runtime's clock; a local move ends when the runtime's local move does.

Wire form (galileo-tasks-bt-ws §2.4): every action carries ``id``, ``type``, ``state``,
``result`` (``""``) and ``progress`` besides its own parameters.
"""

from __future__ import annotations

import logging
import math
import uuid
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from polynav.errors import Conflict, PolynavError
from polynav.geometry import Pose2D, wrap_angle
from polynav.nav.attempt import GoalOptions
from polynav.protocols.galileo.messages import TaskState
from polynav.runtime import events
from polynav.runtime.robot_runtime import RobotRuntime

log = logging.getLogger(__name__)

FINAL = (TaskState.COMPLETE, TaskState.ERROR, TaskState.CANCELLED)


class Outcomes:
    """How each navigation attempt ended, from the runtime's events (drained on each poll)."""

    def __init__(self, runtime: RobotRuntime) -> None:
        self._runtime = runtime
        self._subscription = runtime.bus.subscribe(maxlen=10_000)
        self._ended: dict[int, TaskState] = {}

    def close(self) -> None:
        self._runtime.bus.unsubscribe(self._subscription)

    def ended(self, attempt_id: int) -> TaskState | None:
        """The final state of ``attempt_id``, or ``None`` while it runs (or never ran)."""
        for event in self._subscription.get_nowait():
            if isinstance(event, events.NavigationSucceeded):
                self._ended[event.attempt_id] = TaskState.COMPLETE
            elif isinstance(event, events.NavigationFailed):
                self._ended[event.attempt_id] = TaskState.ERROR
            elif isinstance(event, events.NavigationCanceled):
                self._ended[event.attempt_id] = TaskState.CANCELLED
        while len(self._ended) > 4096:
            del self._ended[next(iter(self._ended))]
        found = self._ended.get(attempt_id)
        if found is not None:
            return found
        snap = self._runtime.status()
        if snap.attempt_id == attempt_id:
            return {"succeeded": TaskState.COMPLETE, "failed": TaskState.ERROR,
                    "canceled": TaskState.CANCELLED}.get(snap.navigation_state)
        return None


@dataclass
class Action:
    """One action of a task; subclasses say what it drives."""

    type: str = field(default="", init=False)
    id: str = field(default_factory=lambda: str(uuid.uuid4()))
    state: TaskState = TaskState.WAITTING
    result: str = ""
    progress: float = 0

    def params(self, runtime: RobotRuntime) -> dict[str, Any]:
        """The action's own wire fields."""
        return {}

    def to_dict(self, runtime: RobotRuntime) -> dict[str, Any]:
        return {"id": self.id, "type": self.type, "state": self.state.value,
                "result": self.result, "progress": self.progress, **self.params(runtime)}

    def start(self, runtime: RobotRuntime) -> None:
        """Begin (between ticks). Raises a polynav error when the robot cannot."""

    def poll(self, runtime: RobotRuntime, outcomes: Outcomes) -> TaskState | None:
        """The final state once ended, else ``None`` (between ticks)."""
        return TaskState.COMPLETE

    def cancel(self, runtime: RobotRuntime) -> None:
        """Stop what the action drives (between ticks)."""

    def reset(self) -> None:
        self.state = TaskState.WAITTING
        self.result = ""
        self.progress = 0


@dataclass
class NavAction(Action):
    """Go to a pose of the current map, or to a named point of it (a charger point docks).

    ``index``/``map_name``/``path`` are the Galileo target point it was made from, if any.
    """

    pose: Pose2D = field(default_factory=lambda: Pose2D(0.0, 0.0, 0.0))
    point: str | None = None
    map_name: str | None = None
    path: str | None = None
    index: int | None = None
    attempt_id: int | None = None
    on_attempt: Callable[[int], None] | None = None
    options: GoalOptions | None = None

    def __post_init__(self) -> None:
        self.type = "nav_action"

    def params(self, runtime: RobotRuntime) -> dict[str, Any]:
        location: dict[str, float] = {"x": -1, "y": -1, "theta": -1}
        distance = -1.0
        if self.state in (TaskState.WORKING, TaskState.PAUSED):
            snap = runtime.status()
            location = {"x": snap.pose.x, "y": snap.pose.y, "theta": snap.pose.theta}
            if snap.attempt_id == self.attempt_id and snap.distance_remaining is not None:
                distance = float(snap.distance_remaining)
        out: dict[str, Any] = {"x": self.pose.x, "y": self.pose.y, "theta": self.pose.theta,
                               "current_location": location, "current_distance": distance,
                               "timeout": 0}
        if self.index is not None:
            out.update({"map": self.map_name, "path": self.path, "index": self.index})
        return out

    def start(self, runtime: RobotRuntime) -> None:
        if self.point is not None:
            self.attempt_id = runtime.go_to(point=self.point, map_name=self.map_name,
                                            options=self.options)
        else:
            self.attempt_id = runtime.go_to(pose=self.pose, map_name=self.map_name,
                                            options=self.options)
        if self.on_attempt is not None:
            self.on_attempt(self.attempt_id)

    def poll(self, runtime: RobotRuntime, outcomes: Outcomes) -> TaskState | None:
        if self.attempt_id is None:
            return TaskState.ERROR
        ended = outcomes.ended(self.attempt_id)
        if ended is TaskState.ERROR:
            snap = runtime.status()
            self.result = snap.reason or "navigation failed" if snap.attempt_id == \
                self.attempt_id else "navigation failed"
        if ended is TaskState.COMPLETE:
            self.progress = 1
        return ended

    def cancel(self, runtime: RobotRuntime) -> None:
        snap = runtime.status()
        if snap.attempt_id == self.attempt_id and snap.navigation_state in ("running", "paused"):
            runtime.cancel()


@dataclass
class ChargeAction(NavAction):
    """Dock onto the charger point (``point``); its pose is the pile's."""

    def __post_init__(self) -> None:
        self.type = "charge_action"

    def params(self, runtime: RobotRuntime) -> dict[str, Any]:
        return {"x": self.pose.x, "y": self.pose.y, "theta": self.pose.theta}


@dataclass
class SleepAction(Action):
    """Wait ``wait_time`` seconds of the runtime's clock."""

    wait_time: float = 0.0
    until: float | None = None

    def __post_init__(self) -> None:
        self.type = "sleep_action"

    def params(self, runtime: RobotRuntime) -> dict[str, Any]:
        return {"wait_time": self.wait_time}

    def start(self, runtime: RobotRuntime) -> None:
        self.until = runtime.now() + self.wait_time

    def poll(self, runtime: RobotRuntime, outcomes: Outcomes) -> TaskState | None:
        assert self.until is not None
        if runtime.now() + 1e-9 >= self.until:
            return TaskState.COMPLETE
        if self.wait_time > 0:
            self.progress = round(1.0 - (self.until - runtime.now()) / self.wait_time, 3)
        return None


@dataclass
class LocalMoveAction(Action):
    """Turn on the spot by ``angle`` [rad], then drive straight ``distance`` [m] (negative:
    backwards), with the runtime's local moves (checked against obstacles)."""

    angle: float = 0.0
    distance: float = 0.0
    method: int = 0
    _steps: list[tuple[str, float]] = field(default_factory=list)

    def __post_init__(self) -> None:
        self.type = "local_move_action"

    def params(self, runtime: RobotRuntime) -> dict[str, Any]:
        return {"angle": self.angle, "distance": self.distance, "method": self.method}

    def planned_steps(self, runtime: RobotRuntime) -> list[tuple[str, float]]:
        return [(kind, value) for kind, value in (("rotate", self.angle),
                                                    ("distance", self.distance))
                if abs(value) > 1e-6]

    def start(self, runtime: RobotRuntime) -> None:
        self._steps = self.planned_steps(runtime)
        self._next(runtime)

    def _next(self, runtime: RobotRuntime) -> bool:
        if not self._steps:
            return False
        kind, value = self._steps.pop(0)
        if kind == "rotate":
            runtime.local_move(rotate=value)
        else:
            runtime.local_move(distance=value)
        return True

    def poll(self, runtime: RobotRuntime, outcomes: Outcomes) -> TaskState | None:
        if runtime.local_move_active:
            return None
        try:
            if self._next(runtime):
                return None
        except PolynavError as exc:
            self.result = str(exc)
            return TaskState.ERROR
        self.progress = 1
        return TaskState.COMPLETE

    def cancel(self, runtime: RobotRuntime) -> None:
        self._steps.clear()
        if runtime.local_move_active:
            try:
                runtime.cancel()
            except Conflict:
                log.debug("local move already ended")


@dataclass
class LocalMoveTargetAction(LocalMoveAction):
    """Reach ``x, y, theta`` (frame ``map`` or ``base_link``) by local moves: turn towards it,
    drive straight, turn to ``theta``; steps smaller than the tolerances are skipped."""

    x: float = 0.0
    y: float = 0.0
    theta: float = 0.0
    frame_id: str = "map"
    xy_tolerance: float = 0.05
    yaw_tolerance: float = 0.05
    timeout: float = 60.0
    start_rotate_enable: bool = True
    target_rotate_enable: bool = True
    deadline: float | None = None

    def __post_init__(self) -> None:
        self.type = "local_move_target_action"

    def params(self, runtime: RobotRuntime) -> dict[str, Any]:
        return {"x": self.x, "y": self.y, "theta": self.theta, "frame_id": self.frame_id,
                "xy_tolerance": self.xy_tolerance, "yaw_tolerance": self.yaw_tolerance,
                "timeout": self.timeout, "start_rotate_enable": self.start_rotate_enable,
                "target_rotate_enable": self.target_rotate_enable}

    def target(self, pose: Pose2D) -> Pose2D:
        """The goal in the map frame, seen from the robot at ``pose``."""
        if self.frame_id == "base_link":
            c, s = math.cos(pose.theta), math.sin(pose.theta)
            return Pose2D(pose.x + c * self.x - s * self.y, pose.y + s * self.x + c * self.y,
                          wrap_angle(pose.theta + self.theta))
        return Pose2D(self.x, self.y, wrap_angle(self.theta))

    def planned_steps(self, runtime: RobotRuntime) -> list[tuple[str, float]]:
        pose = runtime.status().pose
        goal = self.target(pose)
        steps: list[tuple[str, float]] = []
        dx, dy = goal.x - pose.x, goal.y - pose.y
        distance = math.hypot(dx, dy)
        heading = pose.theta
        if distance > self.xy_tolerance:
            bearing = math.atan2(dy, dx)
            turn = wrap_angle(bearing - pose.theta)
            # Reverse rather than turn round when turning at the start is not allowed.
            if not self.start_rotate_enable:
                forward = math.cos(turn) >= 0.0
                steps.append(("distance", distance if forward else -distance))
            else:
                if abs(turn) > self.yaw_tolerance:
                    steps.append(("rotate", turn))
                    heading = bearing
                steps.append(("distance", distance))
        final = wrap_angle(goal.theta - heading)
        if self.target_rotate_enable and abs(final) > self.yaw_tolerance:
            steps.append(("rotate", final))
        return steps

    def start(self, runtime: RobotRuntime) -> None:
        self.deadline = runtime.now() + self.timeout if self.timeout > 0 else None
        super().start(runtime)

    def poll(self, runtime: RobotRuntime, outcomes: Outcomes) -> TaskState | None:
        if self.deadline is not None and runtime.now() > self.deadline:
            self.cancel(runtime)
            self.result = "timeout"
            return TaskState.ERROR
        return super().poll(runtime, outcomes)


@dataclass
class IoAction(Action):
    """Set output ``port`` of the base's IO ("1".."3") to ``level`` ("0" low, "1" high).

    Wire types are the documented strings (galileo-tasks-bt-ws §2.4 #12, A-25). COMPLETE as
    soon as the output is set; ERROR (naming why) when the robot refuses.
    """

    level: int = 0
    port: int = 1

    def __post_init__(self) -> None:
        self.type = "io_action"

    def params(self, runtime: RobotRuntime) -> dict[str, Any]:
        return {"level": str(self.level), "port": str(self.port)}

    def start(self, runtime: RobotRuntime) -> None:
        runtime.peripherals.set_outputs("io", {self.port: self.level})

    def poll(self, runtime: RobotRuntime, outcomes: Outcomes) -> TaskState | None:
        self.progress = 1
        return TaskState.COMPLETE


@dataclass
class SwitchMapAction(Action):
    """Navigate on ``map_name`` from the pose of ``point`` (a route's stop, or the charger)."""

    map_name: str = ""
    path: str = ""
    start_index: int = 0
    point: str | None = None

    def __post_init__(self) -> None:
        self.type = "switch_map_action"

    def params(self, runtime: RobotRuntime) -> dict[str, Any]:
        return {"map": self.map_name, "path": self.path, "start_index": self.start_index}

    def start(self, runtime: RobotRuntime) -> None:
        runtime.start_navigation(self.map_name, point=self.point)

    def poll(self, runtime: RobotRuntime, outcomes: Outcomes) -> TaskState | None:
        snap = runtime.status()
        if snap.mode == "navigating" and snap.map == self.map_name:
            return TaskState.COMPLETE
        if snap.mode == "busy":
            return None
        self.result = f"navigation on {self.map_name} did not start"
        return TaskState.ERROR
