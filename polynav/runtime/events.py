"""Runtime events: what happened to the robot, in polynav's own words, for every adapter.

The runtime publishes one event per change on its :class:`~polynav.runtime.event_bus.EventBus`:
navigation attempts (mapped from the navigator's :mod:`polynav.nav.events`), mode changes,
e-stop, charging, localization and battery. Each event is a frozen value with the time
``stamp`` [s] (simulated or wall clock, the runtime's clock) it happened at, a stable snake_case
``kind`` (``"navigation_succeeded"``) that adapters and the WebSocket use as the event's name,
and :meth:`RuntimeEvent.to_dict` for JSON (poses as ``{"x", "y", "theta"}``).
"""

from __future__ import annotations

import enum
import logging
from dataclasses import dataclass, fields
from typing import ClassVar

from polynav.geometry import Pose2D

log = logging.getLogger(__name__)


def pose_dict(pose: Pose2D) -> dict[str, float]:
    """A pose as JSON: ``{"x", "y", "theta"}`` [m, m, rad]."""
    return {"x": float(pose.x), "y": float(pose.y), "theta": float(pose.theta)}


def _json_value(value: object) -> object:
    if isinstance(value, Pose2D):
        return pose_dict(value)
    if isinstance(value, enum.Enum):
        return value.value
    if isinstance(value, bool) or value is None or isinstance(value, str | int):
        return value
    if isinstance(value, float):
        return float(value)
    if isinstance(value, tuple | list):
        return [_json_value(item) for item in value]
    return str(value)


@dataclass(frozen=True, slots=True)
class RuntimeEvent:
    """Base of every runtime event; ``stamp`` [s] is on the runtime's clock."""

    kind: ClassVar[str] = "event"

    stamp: float

    def to_dict(self) -> dict[str, object]:
        """The event as JSON-ready values, with its ``kind``."""
        out: dict[str, object] = {"kind": self.kind}
        for f in fields(self):
            out[f.name] = _json_value(getattr(self, f.name))
        return out


@dataclass(frozen=True, slots=True)
class ModeChanged(RuntimeEvent):
    """The robot's mode changed (``"free"``, ``"busy"``, ``"navigating"``, ``"mapping"``)."""

    kind: ClassVar[str] = "mode_changed"

    old: str
    new: str


@dataclass(frozen=True, slots=True)
class NavigationStarted(RuntimeEvent):
    """A goal was accepted; ``point`` names it when it was given by name."""

    kind: ClassVar[str] = "navigation_started"

    attempt_id: int
    goal: Pose2D
    point: str | None = None


@dataclass(frozen=True, slots=True)
class NavigationSucceeded(RuntimeEvent):
    """The robot reached the goal; ``distance`` [m] is how far it travelled for it;
    ``position_uncertainty`` [m] and ``heading_uncertainty`` [rad] how well localization knew
    the pose there (one standard deviation; ``None``: the localizer does not say)."""

    kind: ClassVar[str] = "navigation_succeeded"

    attempt_id: int
    distance: float
    position_uncertainty: float | None = None
    heading_uncertainty: float | None = None


@dataclass(frozen=True, slots=True)
class NavigationFailed(RuntimeEvent):
    """The attempt gave up; ``reason`` is a :class:`~polynav.nav.attempt.FailureReason` value;
    ``planned``: whether any path was ever found (if not, the goal was unreachable)."""

    kind: ClassVar[str] = "navigation_failed"

    attempt_id: int
    reason: str
    distance: float
    planned: bool = True


@dataclass(frozen=True, slots=True)
class NavigationCanceled(RuntimeEvent):
    kind: ClassVar[str] = "navigation_canceled"

    attempt_id: int
    distance: float


@dataclass(frozen=True, slots=True)
class NavigationPaused(RuntimeEvent):
    kind: ClassVar[str] = "navigation_paused"

    attempt_id: int


@dataclass(frozen=True, slots=True)
class NavigationResumed(RuntimeEvent):
    kind: ClassVar[str] = "navigation_resumed"

    attempt_id: int


@dataclass(frozen=True, slots=True)
class NavigationRetry(RuntimeEvent):
    """A retry: ``retries`` so far in this attempt, ``cause`` what failed (``"blocked"``...)."""

    kind: ClassVar[str] = "navigation_retry"

    attempt_id: int
    retries: int
    cause: str


@dataclass(frozen=True, slots=True)
class NavigationStuck(RuntimeEvent):
    """The robot made no progress along its path (a recovery follows as a retry)."""

    kind: ClassVar[str] = "navigation_stuck"

    attempt_id: int


@dataclass(frozen=True, slots=True)
class PlanningFailed(RuntimeEvent):
    """A global plan failed during an attempt; ``cause`` is ``"start_unknown"`` (the robot
    stands in unknown space), ``"start_occupied"`` (on or in an obstacle), ``"goal_occupied"``,
    ``"outside_map"``, ``"walled_in_unknown"`` (unknown space, taken as an obstacle, is all that
    parts the robot from the goal) or ``"no_path"``. The attempt retries or fails as the
    navigator decides."""

    kind: ClassVar[str] = "planning_failed"

    attempt_id: int
    cause: str


@dataclass(frozen=True, slots=True)
class NavigationBlocked(RuntimeEvent):
    """The controller stopped in front of an obstacle on the path (it waits, then re-plans)."""

    kind: ClassVar[str] = "navigation_blocked"

    attempt_id: int


@dataclass(frozen=True, slots=True)
class NavigationWaiting(RuntimeEvent):
    """The robot stands and waits: ``cause`` ``"person"``, people block the way and it waits
    for them to make way (each dialect's "please make way"), re-planning as soon as the way
    opens or another way exists; ``"goal occupied"``, something not on the map (another robot)
    stands on the goal, and it goes on once the goal is free."""

    kind: ClassVar[str] = "navigation_waiting"

    attempt_id: int
    cause: str


@dataclass(frozen=True, slots=True)
class TrafficBusy(RuntimeEvent):
    """The narrow passage (traffic ``zone``) on the robot's way is held by another robot: the
    fleet queued the robot's request for it. Once per zone until the robot gets it or no
    longer needs it."""

    kind: ClassVar[str] = "traffic_busy"

    attempt_id: int
    zone: str


@dataclass(frozen=True, slots=True)
class TrafficWaitStarted(RuntimeEvent):
    """The robot stopped in front of (or inside) narrow passage ``zone`` that another robot
    holds, and waits for it (moving up in line is still the same wait)."""

    kind: ClassVar[str] = "traffic_wait_started"

    attempt_id: int
    zone: str


@dataclass(frozen=True, slots=True)
class TrafficWaitEnded(RuntimeEvent):
    """The wait for ``zone`` is over: ``granted`` when the robot got the passage and goes on,
    otherwise its goal ended or changed and it no longer needs it."""

    kind: ClassVar[str] = "traffic_wait_ended"

    attempt_id: int
    zone: str
    granted: bool


@dataclass(frozen=True, slots=True)
class NoEntrySignSeen(RuntimeEvent):
    """The robot's sign camera spotted a "no entry" sign at (``x``, ``y``) [m, map frame]
    during attempt ``attempt_id``: the way it stands in is closed (the navigator stops and
    plans round it, or the goal fails). Once per sign and map."""

    kind: ClassVar[str] = "no_entry_sign_seen"

    attempt_id: int
    x: float
    y: float


@dataclass(frozen=True, slots=True)
class ExplorationFinished(RuntimeEvent):
    """Exploration found no frontier left and brought the robot back to where it began;
    ``targets`` frontiers were driven to."""

    kind: ClassVar[str] = "exploration_finished"

    targets: int


@dataclass(frozen=True, slots=True)
class AttemptEvent(RuntimeEvent):
    """A step of navigation attempt ``attempt_id`` that carries nothing else."""

    attempt_id: int


@dataclass(frozen=True, slots=True)
class ChargerLeaveStarted(AttemptEvent):
    """The attempt began on a charger: the robot backs off it before planning."""

    kind: ClassVar[str] = "charger_leave_started"


@dataclass(frozen=True, slots=True)
class ChargerLeaveRetry(RuntimeEvent):
    """Leaving the charger made no headway for a while (an e-stop, an obstacle): retrying."""

    kind: ClassVar[str] = "charger_leave_retry"

    attempt_id: int
    retries: int


@dataclass(frozen=True, slots=True)
class ChargerLeft(AttemptEvent):
    kind: ClassVar[str] = "charger_left"


@dataclass(frozen=True, slots=True)
class ChargerLeaveFailed(AttemptEvent):
    """The robot could not get off the charger; the attempt fails next."""

    kind: ClassVar[str] = "charger_leave_failed"


@dataclass(frozen=True, slots=True)
class DockingStarted(AttemptEvent):
    """Attempt ``attempt_id`` reached the approach of its charger and starts docking."""

    kind: ClassVar[str] = "docking_started"


@dataclass(frozen=True, slots=True)
class DockingSucceeded(AttemptEvent):
    """Charging contact made; the attempt succeeds next."""

    kind: ClassVar[str] = "docking_succeeded"


@dataclass(frozen=True, slots=True)
class DockingFailed(RuntimeEvent):
    """Docking gave up; ``cause`` is ``"no_feature"`` (no charger's plate in the scan near the
    marker), ``"no_infrared"`` (its infrared beacon not seen), ``"bad_data"`` (the contacts
    touch but the charger's data link gave no valid frame), ``"no_contact"`` (on the charger
    pose but no charging current) or ``"timeout"``. The attempt fails next."""

    kind: ClassVar[str] = "docking_failed"

    attempt_id: int
    cause: str


@dataclass(frozen=True, slots=True)
class PatrolEvent(RuntimeEvent):
    """Base of a patrol's (a cruise over points) events: what it runs over."""

    patrol_id: int
    points: tuple[str, ...]
    count: int
    tolerance: float


@dataclass(frozen=True, slots=True)
class PatrolStarted(PatrolEvent):
    kind: ClassVar[str] = "patrol_started"


@dataclass(frozen=True, slots=True)
class PatrolFinished(PatrolEvent):
    kind: ClassVar[str] = "patrol_finished"


@dataclass(frozen=True, slots=True)
class PatrolFailed(PatrolEvent):
    """The last leg of the last round failed."""

    kind: ClassVar[str] = "patrol_failed"


@dataclass(frozen=True, slots=True)
class PatrolCanceled(PatrolEvent):
    kind: ClassVar[str] = "patrol_canceled"


@dataclass(frozen=True, slots=True)
class PowerOffNotice(RuntimeEvent):
    """The robot powers off ``after`` seconds from now (then on again if ``reboot``, ``delay``
    seconds after the power-off)."""

    kind: ClassVar[str] = "power_off_notice"

    reboot: bool
    after: float
    delay: float


@dataclass(frozen=True, slots=True)
class SoftwareShutdownNotice(RuntimeEvent):
    """The navigation software is about to stop (a restart or an update follows)."""

    kind: ClassVar[str] = "software_shutdown_notice"


@dataclass(frozen=True, slots=True)
class RobotDisplaced(RuntimeEvent):
    """The robot moved without being driven (pushed or carried by hand) by ``distance`` [m]."""

    kind: ClassVar[str] = "robot_displaced"

    distance: float


@dataclass(frozen=True, slots=True)
class ForeignObjectDetected(RuntimeEvent):
    """Something sits inside the robot's body (the lidar sees returns closer than its own
    housing allows over ``sector`` [rad] of its field of view)."""

    kind: ClassVar[str] = "foreign_object_detected"

    sector: float


@dataclass(frozen=True, slots=True)
class EStopChanged(RuntimeEvent):
    """The hardware button or the software e-stop changed; ``active`` is either of them."""

    kind: ClassVar[str] = "estop_changed"

    hardware: bool
    software: bool
    active: bool


@dataclass(frozen=True, slots=True)
class ChargeChanged(RuntimeEvent):
    kind: ClassVar[str] = "charge_changed"

    charging: bool


@dataclass(frozen=True, slots=True)
class LocalizationChanged(RuntimeEvent):
    """Localization state changed (``"uninitialized"``, ``"tracking"``, ``"lost"``)."""

    kind: ClassVar[str] = "localization_changed"

    state: str
    quality: float


@dataclass(frozen=True, slots=True)
class LowBattery(RuntimeEvent):
    """The battery fell below the low-battery threshold (once per crossing)."""

    kind: ClassVar[str] = "low_battery"

    percent: float


@dataclass(frozen=True, slots=True)
class PoseInitialized(RuntimeEvent):
    """Localization was (re)started near ``pose`` (map frame)."""

    kind: ClassVar[str] = "pose_initialized"

    pose: Pose2D


@dataclass(frozen=True, slots=True)
class TaskChanged(RuntimeEvent):
    """A node of a task changed state (the root's ``node_id`` is the task's ``task_id``
    node): ``state`` in the vendor spelling (``WORKING``, ``COMPLETE``, ``FAIL``...)."""

    kind: ClassVar[str] = "task_changed"

    task_id: str
    task_name: str
    owner: str
    node_id: str
    node_kind: str
    state: str
    root: bool
    result: str = ""


@dataclass(frozen=True, slots=True)
class AutoChargeStarted(RuntimeEvent):
    """The battery fell below the low threshold: the robot heads for ``charger`` (the running
    task, if any, waits paused)."""

    kind: ClassVar[str] = "auto_charge_started"

    percent: float
    charger: str
    task_id: str | None


@dataclass(frozen=True, slots=True)
class AutoChargeEnded(RuntimeEvent):
    """Auto-charge ended: ``charged`` to the full threshold (the waiting task goes on), or
    not (``reason``; the waiting task is cancelled)."""

    kind: ClassVar[str] = "auto_charge_ended"

    charged: bool
    percent: float
    reason: str = ""


@dataclass(frozen=True, slots=True)
class ScheduleFired(RuntimeEvent):
    """Schedule ``schedule_id`` started task ``task_id`` for its start due at ``due`` (ISO
    date-time on the robot's calendar); ``starts`` counts its starts so far."""

    kind: ClassVar[str] = "schedule_fired"

    schedule_id: str
    task_id: str
    due: str
    starts: int


@dataclass(frozen=True, slots=True)
class ScheduleSkipped(RuntimeEvent):
    """Schedule ``schedule_id`` did not start task ``task_id`` for its start due at ``due``:
    ``reason`` says why (the robot was off then, stayed busy, the task could not start)."""

    kind: ClassVar[str] = "schedule_skipped"

    schedule_id: str
    task_id: str
    due: str
    reason: str
