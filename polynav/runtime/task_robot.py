"""The runtime as the task engine's robot (:class:`polynav.tasks.robot.TaskRobot`).

Every method runs between ticks, on the runtime's loop (the engine is ticked from the control
loop, and its commands run through :meth:`RobotRuntime.run_between_ticks`), so it may use the
runtime's own parts directly. How each goal ended is taken from the runtime's navigation
events as they are published (:meth:`RuntimeTaskRobot.note`), so an outcome is never missed
between two ticks of the engine.

What a task starts that outlives its action (a video recording, a lift car held between the
call and the ride) is stopped or given back when the task ends, however it ends: the robot
sees the task's root end in the same events (``task_changed``).
"""

from __future__ import annotations

import logging
from collections import OrderedDict
from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING, Any

from polynav.errors import Conflict, PolynavError
from polynav.geometry import Pose2D
from polynav.nav.attempt import GoalOptions
from polynav.robot.devices import AxisMode, DeviceJob, JobState, PtzPose
from polynav.runtime import events
from polynav.tasks.robot import (
    CallbackAnswer,
    CameraLogin,
    GoalEnd,
    GoalOutcome,
    LiftCall,
    TransferOutcome,
)

if TYPE_CHECKING:
    from polynav.runtime.robot_runtime import RobotRuntime

log = logging.getLogger(__name__)

_KEEP = 4096  # outcomes remembered
_ENDED = frozenset({"COMPLETE", "FAIL", "ERROR", "CANCELLED"})


class RuntimeTaskRobot:
    """One runtime, seen by its task engine."""

    def __init__(self, runtime: RobotRuntime) -> None:
        self._runtime = runtime
        self._outcomes: OrderedDict[int, GoalOutcome] = OrderedDict()
        # What to stop when a task ends, by task id and by what it stops (one recorder, one
        # held car: the latest registration is the one that matters, so a task looping for
        # ever keeps a bounded list).
        self._at_end: dict[str, dict[str, Callable[[], None]]] = {}

    def note(self, event: events.RuntimeEvent) -> None:
        """Keep how each goal ended, and clean up after a task that ended (called for every
        runtime event)."""
        if isinstance(event, events.TaskChanged):
            if event.root and event.state in _ENDED:
                self._task_ended(event.task_id)
            return
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

    # -- camera, media, axes -------------------------------------------------------------------

    def take_photo(self, view: str, name: str | None) -> str:
        return self._runtime.peripherals.take_photo(view, name) + ".png"

    def start_video(self, view: str, duration: float, name: str | None, *,
                    task_id: str) -> str:
        peripherals = self._runtime.peripherals
        job, stem = peripherals.start_video(view, duration, name)

        def stop() -> None:
            running = peripherals.job(job.job_id)
            if running is not None and running.state is JobState.WORKING:
                peripherals.stop_video()

        self._when_ended(task_id, "video", stop)
        return stem + ".mkv"

    def dock_cart(self, *, cart: str | None, point: str | None, cabin_id: str | None) -> int:
        self._runtime.carts.dock(cart=cart, point=point, cabin_id=cabin_id)
        return self._runtime.carts.count

    def leave_cart(self, *, point: str | None, map_name: str | None) -> int:
        self._runtime.carts.leave(point=point, map_name=map_name)
        return self._runtime.carts.count

    def cart_outcome(self, number: int) -> tuple[bool, str, str] | None:
        return self._runtime.carts.outcome(number)

    def cancel_cart(self) -> None:
        self._runtime.carts.cancel()

    def move_axis(self, axis: str, mode: AxisMode, *, target: float = 0.0, speed: float = 0.0,
                  duration: float = 0.0) -> str:
        job = self._runtime.peripherals.move_axis(axis, mode, target=target, speed=speed,
                                                  duration=duration)
        return job.job_id

    def axis_job(self, job_id: str) -> DeviceJob | None:
        return self._runtime.peripherals.job(job_id)

    def axis_position(self, axis: str) -> float:
        return float(self._runtime.peripherals.axis_state(axis).position)

    def stop_axis(self, axis: str) -> None:
        self._runtime.peripherals.stop_axis(axis)

    def ptz_move(self, camera: CameraLogin, pose: PtzPose) -> None:
        ptz = self._runtime.peripherals.devices.ptz_camera
        ptz.check_login(camera.ip, camera.port, camera.username, camera.password)
        self._runtime.peripherals.ptz(lambda now: ptz.move_to(now, pose))

    def ptz_pose(self) -> PtzPose:
        return self._runtime.peripherals.ptz_pose()

    def ptz_stop(self) -> None:
        ptz = self._runtime.peripherals.devices.ptz_camera
        self._runtime.peripherals.ptz(lambda now: ptz.move_speed(now, 0.0, 0.0, 0.0))

    def ptz_snapshot(self, camera: CameraLogin) -> str:
        peripherals = self._runtime.peripherals
        peripherals.devices.ptz_camera.check_login(camera.ip, camera.port, camera.username,
                                                   camera.password)
        return peripherals.ptz_snapshot().name

    # -- callbacks -----------------------------------------------------------------------------

    def start_callback(self, url: str, method: str, data: Mapping[str, Any],
                       timeout: float) -> int:
        return self._runtime.callbacks.start(url, method, data, timeout)

    def callback_answer(self, call_id: int) -> CallbackAnswer | None:
        result = self._runtime.callbacks.result(call_id)
        if result is None:
            return None
        return CallbackAnswer(result.status, result.body, result.error)

    def drop_callback(self, call_id: int) -> None:
        self._runtime.callbacks.forget(call_id)

    # -- lifts ---------------------------------------------------------------------------------

    def call_lift(self, *, car: str | None, level: int | None, task_id: str) -> LiftCall:
        runtime = self._runtime
        hold = runtime.hold_lift(car, level)

        def give_back() -> None:
            held = runtime.held_lift()
            if held is not None and held.car == hold.car:
                runtime.release_lift()

        self._when_ended(task_id, "lift", give_back)
        call = self.lift_call()
        assert call is not None
        return call

    def lift_call(self) -> LiftCall | None:
        hold = self._runtime.held_lift()
        if hold is None:
            return None
        state = self._runtime.lift(hold.car).state()
        return LiftCall(hold.car, hold.floor, hold.placed,
                        hold.placed and state.ready_at(hold.floor), state.full, hold.refused)

    def release_lift(self) -> None:
        self._runtime.release_lift()

    # -- tasks ending --------------------------------------------------------------------------

    def _when_ended(self, task_id: str, what: str, fn: Callable[[], None]) -> None:
        self._at_end.setdefault(task_id, {})[what] = fn

    def _task_ended(self, task_id: str) -> None:
        for fn in self._at_end.pop(task_id, {}).values():
            try:
                fn()
            except PolynavError:  # the task is over either way; say what was left running
                log.error("task %s: not cleaned up after", task_id, exc_info=True)

    def trigger_automation(self, key: str) -> str:
        return str(self._runtime.automations.trigger(key)["id"])

    # -- maps ------------------------------------------------------------------------------

    def upload_map(self, server_id: str) -> int:
        self._runtime.map_exchange.url(server_id)  # an unknown server first: it names why
        name = self._runtime.map_name
        if name is None or self._runtime.mapless:
            raise Conflict("no map in use to upload: start navigation on a map first")
        return self._runtime.map_exchange.upload(server_id, name,
                                                 self._runtime.store.load_map(name))

    def download_map(self, server_id: str, map_id: str) -> int:
        store = self._runtime.store
        return self._runtime.map_exchange.download(
            server_id, map_id, lambda grid: store.save_map(map_id, grid))

    def transfer(self, transfer_id: int) -> TransferOutcome | None:
        exchange = self._runtime.map_exchange
        result = exchange.result(transfer_id)
        if result is None:
            return None
        exchange.forget(transfer_id)
        return TransferOutcome(result.ok, result.error)
