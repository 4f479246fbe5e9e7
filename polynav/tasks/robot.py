"""What a task may ask of its robot: the runtime's commands, as the task engine sees them.

The engine is a service below the runtime (DESIGN §1): it never imports the runtime. The
runtime hands it a :class:`TaskRobot` (:mod:`polynav.runtime.task_robot`) whose methods are
called between ticks, on the loop, and raise the runtime's errors
(:class:`~polynav.errors.PolynavError`) when the robot cannot do what is asked.
"""

from __future__ import annotations

import enum
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Protocol

from polynav.geometry import Pose2D
from polynav.nav.attempt import GoalOptions
from polynav.robot.devices import AxisMode, DeviceJob, PtzPose


class GoalEnd(enum.Enum):
    """How a navigation goal ended."""

    SUCCEEDED = "succeeded"
    FAILED = "failed"
    CANCELED = "canceled"


@dataclass(frozen=True, slots=True)
class GoalOutcome:
    """A goal's end: how, and why it failed (a :class:`~polynav.nav.attempt.FailureReason`
    value such as ``"no path"``, or the runtime's message)."""

    end: GoalEnd
    reason: str = ""


@dataclass(frozen=True, slots=True)
class CameraLogin:
    """Where a network (ONVIF) camera is and how to log in; ``ip`` empty: the first camera
    found."""

    ip: str
    port: int
    username: str
    password: str


@dataclass(frozen=True, slots=True)
class CallbackAnswer:
    """How an HTTP callback ended: ``status`` (0: no answer), the answer's text, or
    ``error`` (a network error, a timeout)."""

    status: int
    body: str = ""
    error: str = ""


@dataclass(frozen=True, slots=True)
class LiftCall:
    """A car held for the task and asked to ``floor``: ``placed`` once the car took the call,
    ``ready`` while it stands there with its doors open, ``full`` with no room for another
    rider, ``refused`` why the car turned the call down (occupied, out of service)."""

    car: str
    floor: str
    placed: bool
    ready: bool
    full: bool
    refused: str = ""


@dataclass(frozen=True, slots=True)
class TransferOutcome:
    """A map transfer's end: ``ok``, or why not."""

    ok: bool
    reason: str = ""


class TaskRobot(Protocol):
    """The robot, for the task engine; every call between ticks."""

    def now(self) -> float:
        """The runtime's clock [s]."""
        ...

    def pose(self) -> Pose2D:
        """The pose estimate on the current map."""
        ...

    def current_map(self) -> str | None:
        """The map navigation runs on; ``None`` while not navigating."""
        ...

    def battery_percent(self) -> float: ...

    def charging(self) -> bool:
        """Whether the robot stands on a charger that charges it."""
        ...

    # -- navigation ----------------------------------------------------------------------------

    def navigate(self, *, point: str | None = None, pose: Pose2D | None = None,
                 map_name: str | None = None, options: GoalOptions | None = None) -> int:
        """Start a goal (on another map: across lifts and connections); its attempt id."""
        ...

    def goal_outcome(self, attempt_id: int) -> GoalOutcome | None:
        """How the goal ended; ``None`` while it runs."""
        ...

    def distance_remaining(self, attempt_id: int) -> float | None: ...

    def pause_goal(self, attempt_id: int) -> None: ...

    def resume_goal(self, attempt_id: int) -> None: ...

    def cancel_goal(self, attempt_id: int) -> None:
        """Cancel the goal if it still runs."""
        ...

    def switch_map(self, map_name: str, point: str | None) -> None:
        """Start navigation on ``map_name`` from ``point`` (the robot stands there)."""
        ...

    def navigation_ready(self, map_name: str) -> bool | None:
        """``True`` navigating on the map, ``None`` while loading, ``False`` if it did not
        start."""
        ...

    # -- motion --------------------------------------------------------------------------------

    def local_move(self, *, rotate: float | None = None, distance: float | None = None) -> None:
        """Turn on the spot [rad] or drive straight [m], checked against obstacles."""
        ...

    def local_move_active(self) -> bool: ...

    def stop_local_move(self) -> None: ...

    # -- devices -------------------------------------------------------------------------------

    def set_output(self, port: int, level: int) -> None:
        """Set an output of the base's IO bank."""
        ...

    def say(self, text: str) -> float:
        """Speak ``text``; how long it takes [s]."""
        ...

    def stop_speaking(self) -> None: ...

    def change_settings(self, changes: Mapping[str, Any]) -> dict[str, Any]:
        """Apply setting changes; the values they replaced."""
        ...

    # -- camera, media, axes -------------------------------------------------------------------

    def take_photo(self, view: str, name: str | None) -> str:
        """Save a photo of camera ``view`` (``front``, ``back``); its file name."""
        ...

    def start_video(self, view: str, duration: float, name: str | None, *,
                    task_id: str) -> str:
        """Record ``duration`` [s] of camera ``view``, stopped early when task ``task_id``
        ends; the video's file name."""
        ...

    def move_axis(self, axis: str, mode: AxisMode, *, target: float = 0.0, speed: float = 0.0,
                  duration: float = 0.0) -> str:
        """Start a move of ``slide``, ``jacking`` or ``jacking_rotation``; its job id."""
        ...

    def axis_job(self, job_id: str) -> DeviceJob | None: ...

    def axis_position(self, axis: str) -> float:
        """Where the axis stands [m or rad from zero]."""
        ...

    def stop_axis(self, axis: str) -> None: ...

    def ptz_move(self, camera: CameraLogin, pose: PtzPose) -> None:
        """Move the network camera to an absolute pan, tilt and zoom."""
        ...

    def ptz_pose(self) -> PtzPose: ...

    def ptz_stop(self) -> None: ...

    def ptz_snapshot(self, camera: CameraLogin) -> str:
        """Save a snapshot of the network camera; its file name."""
        ...

    # -- callbacks -----------------------------------------------------------------------------

    def start_callback(self, url: str, method: str, data: Mapping[str, Any],
                       timeout: float) -> int:
        """Send an HTTP request off the loop (hosts as the runtime allows); its id."""
        ...

    def callback_answer(self, call_id: int) -> CallbackAnswer | None:
        """How the callback ended; ``None`` while it waits."""
        ...

    def drop_callback(self, call_id: int) -> None: ...

    # -- lifts ---------------------------------------------------------------------------------

    def dock_cart(self, *, cart: str | None, point: str | None, cabin_id: str | None) -> int:
        """Start docking to a cart or cabin; the dock's number (:meth:`cart_outcome`)."""
        ...

    def leave_cart(self, *, point: str | None, map_name: str | None) -> int:
        """Start leaving the load (at ``point`` first when given); the leave's number."""
        ...

    def cart_outcome(self, number: int) -> tuple[bool, str, str] | None:
        """Once dock or leave ``number`` ended: whether it succeeded, the load's name, the
        reason it failed; ``None`` while it runs."""
        ...

    def cancel_cart(self) -> None:
        """Stop the dock or leave under way, if any."""
        ...

    def call_lift(self, *, car: str | None, level: int | None, task_id: str) -> LiftCall:
        """Hold a car (``car``, else the one held, else the nearest) and ask it to the floor
        at ``level`` (``None``: the robot's) with its doors open; given back when task
        ``task_id`` ends, or by :meth:`release_lift`."""
        ...

    def lift_call(self) -> LiftCall | None:
        """The car held and how its call stands; ``None`` when none is held."""
        ...

    def release_lift(self) -> None:
        """End the held car's session (nothing when none is held)."""
        ...

    def trigger_automation(self, key: str) -> str:
        """Run the enabled automation task that ``key`` triggers; the run's id. Raises
        NotFound when none has it, Conflict when automations are off."""
        ...

    # -- maps ------------------------------------------------------------------------------

    def upload_map(self, server_id: str) -> int:
        """Send the map in use to dispatch server ``server_id``; the transfer's id. Raises
        NotFound (no such server), Conflict (no map in use)."""
        ...

    def download_map(self, server_id: str, map_id: str) -> int:
        """Fetch map ``map_id`` from ``server_id`` into the site; the transfer's id."""
        ...

    def transfer(self, transfer_id: int) -> TransferOutcome | None:
        """How a map transfer ended; ``None`` while it runs."""
        ...
