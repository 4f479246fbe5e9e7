"""The runtime as the task engine's robot (:class:`polynav.tasks.robot.TaskRobot`).

Every method runs between ticks, on the runtime's loop (the engine is ticked from the control
loop, and its commands run through :meth:`RobotRuntime.run_between_ticks`), so it may use the
runtime's own parts directly. How each goal ended is taken from the runtime's navigation
events as they are published (:meth:`RuntimeTaskRobot.note`), so an outcome is never missed
between two ticks of the engine.
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

from polynav.geometry import Pose2D
from polynav.nav.attempt import GoalOptions
from polynav.runtime import events
from polynav.tasks.robot import GoalEnd, GoalOutcome

if TYPE_CHECKING:
    from polynav.runtime.robot_runtime import RobotRuntime

_KEEP = 4096  # outcomes remembered


class RuntimeTaskRobot:
    """One runtime, seen by its task engine."""

    def __init__(self, runtime: RobotRuntime) -> None:
        self._runtime = runtime
        self._outcomes: OrderedDict[int, GoalOutcome] = OrderedDict()

    def note(self, event: events.RuntimeEvent) -> None:
        """Keep how each goal ended (called for every runtime event)."""
        if isinstance(event, events.NavigationSucceeded):
            outcome = GoalOutcome(GoalEnd.SUCCEEDED)
        elif isinstance(event, events.NavigationFailed):
            outcome = GoalOutcome(GoalEnd.FAILED, event.reason)
        elif isinstance(event, events.NavigationCanceled):
            outcome = GoalOutcome(GoalEnd.CANCELED)
        else:
            return
        self._outcomes[event.attempt_id] = outcome
        while len(self._outcomes) > _KEEP:
            self._outcomes.popitem(last=False)

    def now(self) -> float:
        return self._runtime.now()

    def pose(self) -> Pose2D:
        return self._runtime.status().pose

    def current_map(self) -> str | None:
        return self._runtime.map_name

    def battery_percent(self) -> float:
        return float(self._runtime.robot.read_battery().percent)

    def charging(self) -> bool:
        return bool(self._runtime.robot.read_battery().charging)

    # -- navigation ----------------------------------------------------------------------------

    def navigate(self, *, point: str | None = None, pose: Pose2D | None = None,
                 map_name: str | None = None, options: GoalOptions | None = None) -> int:
        return self._runtime.go_to(point=point, pose=pose, map_name=map_name, options=options)

    def goal_outcome(self, attempt_id: int) -> GoalOutcome | None:
        return self._outcomes.get(attempt_id)

    def _mine(self, attempt_id: int, *states: str) -> bool:
        snap = self._runtime.status()
        return snap.attempt_id == attempt_id and snap.navigation_state in states

    def distance_remaining(self, attempt_id: int) -> float | None:
        snap = self._runtime.status()
        return snap.distance_remaining if snap.attempt_id == attempt_id else None

    def pause_goal(self, attempt_id: int) -> None:
        if self._mine(attempt_id, "running"):
            self._runtime.pause()

    def resume_goal(self, attempt_id: int) -> None:
        if self._mine(attempt_id, "paused"):
            self._runtime.resume()

    def cancel_goal(self, attempt_id: int) -> None:
        if self._mine(attempt_id, "running", "paused"):
            self._runtime.cancel()

    def switch_map(self, map_name: str, point: str | None) -> None:
        self._runtime.start_navigation(map_name, point=point)

    def navigation_ready(self, map_name: str) -> bool | None:
        snap = self._runtime.status()
        if snap.mode == "navigating" and snap.map == map_name:
            return True
        return None if snap.mode == "busy" else False

    # -- motion --------------------------------------------------------------------------------

    def local_move(self, *, rotate: float | None = None, distance: float | None = None) -> None:
        self._runtime.local_move(rotate=rotate, distance=distance)

    def local_move_active(self) -> bool:
        return self._runtime.local_move_active

    def stop_local_move(self) -> None:
        if self._runtime.local_move_active:
            self._runtime.cancel()

    # -- devices -------------------------------------------------------------------------------

    def set_output(self, port: int, level: int) -> None:
        self._runtime.peripherals.set_outputs("io", {port: level})

    def say(self, text: str) -> float:
        return self._runtime.peripherals.say(text)

    def stop_speaking(self) -> None:
        self._runtime.peripherals.stop_speaking()

    def change_settings(self, changes: Mapping[str, Any]) -> dict[str, Any]:
        current = self._runtime.settings().to_dict()
        old = {key: current.get(key) for key in changes}
        self._runtime.update_settings(changes)
        return old
