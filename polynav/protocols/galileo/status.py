"""GalileoStatus and ``/system/status`` from the runtime's status snapshot (issue item 9).

Spec galileo-http-a §1.5–1.6. Every field is derived from the prebuilt
:class:`~polynav.runtime.status.StatusSnapshot` (O(1), no runtime call), plus the adapter's own
record of which Galileo target an attempt was sent to, and the pack voltage.

Decisions where the spec is silent (``docs/galileo.md``):

* ``visualStatus``: ``-1`` (visual system off) while neither navigating nor mapping; otherwise
  from localization: uninitialized ``0``, tracking ``1``, lost ``2``; a tracking estimate whose
  scan-to-map quality is below :data:`LOST_QUALITY` also reads ``2``.
* ``targetNumID``: the target point index of the attempt this adapter started from a target
  point, ``-2`` for any other goal (a pose goal, or a goal from another dialect), ``-1`` when
  no attempt is current. The charge pile is index ``-1`` in ``start_index`` but reads ``-2``
  here, since ``-1`` already means "invalid" in this field.
* ``targetStatus``/``angleGoalStatus``/``targetDistance`` follow the current or last attempt:
  running 1/0/remaining path length, paused 2/0/remaining, succeeded 0/1/0.0, failed 3/2/-1,
  canceled 0/-1/-1, none -1/-1/-1.
* ``currentAngle`` in radians (A-14), ``controlSpeed*`` are the measured speeds (the runtime
  publishes no separate command).
* ``header.stamp`` is the snapshot's time on the runtime's clock (simulated time in simulation).
"""

from __future__ import annotations

import logging
import math
from typing import Any

from polynav.errors import NotFound, PolynavError
from polynav.protocols.galileo import task_objects as objects
from polynav.protocols.galileo.context import TARGET_WITHOUT_ID, Context, Target
from polynav.protocols.galileo.endpoint import Reply, RouteList
from polynav.protocols.galileo.messages import (
    AngleGoalStatus,
    ChargeStatus,
    GbaStatus,
    LoopStatus,
    MapStatus,
    NavStatus,
    SystemState,
    TargetStatus,
    VisualStatus,
)
from polynav.protocols.galileo.native.marks import marks
from polynav.protocols.galileo.params import Params
from polynav.runtime.status import StatusSnapshot

log = logging.getLogger(__name__)

ROUTES = RouteList()

#: Scan-to-map quality under which a tracking estimate reads as lost (visualStatus 2).
LOST_QUALITY = 0.2
#: Charge [%] from which a charging robot reads as charged (trickle charging, chargeStatus 2).
CHARGED_PERCENT = 99.5
#: ``start_index`` of the charge pile (galileo-http-b §1.5).
CHARGE_PILE_INDEX = -1

_SYSTEM_STATE = {
    "free": SystemState.FREE,
    "mapping": SystemState.MAPPING,
    "navigating": SystemState.NAVIGATING,
    "busy": SystemState.BUSY,
}

_VISUAL = {
    "uninitialized": VisualStatus.UNINIT,
    "tracking": VisualStatus.TRACKING,
    "lost": VisualStatus.LOST,
}

# navigation_state -> (targetStatus, angleGoalStatus)
_TARGET = {
    "running": (TargetStatus.WORKING, AngleGoalStatus.NOT_DONE),
    "paused": (TargetStatus.PAUSED, AngleGoalStatus.NOT_DONE),
    "succeeded": (TargetStatus.FREE, AngleGoalStatus.DONE),
    "failed": (TargetStatus.ERROR, AngleGoalStatus.ERROR),
    "canceled": (TargetStatus.FREE, AngleGoalStatus.INVALID),
}


_RUNNING_TASK = frozenset({"WAITTING", "WORKING", "PAUSED"})

# an angle command's task state -> angleGoalStatus
_ANGLE = {
    "WAITTING": AngleGoalStatus.NOT_DONE, "WORKING": AngleGoalStatus.NOT_DONE,
    "PAUSED": AngleGoalStatus.NOT_DONE, "COMPLETE": AngleGoalStatus.DONE,
    "CANCELLED": AngleGoalStatus.INVALID,
}


def system_state(snapshot: StatusSnapshot) -> SystemState:
    return _SYSTEM_STATE.get(snapshot.mode, SystemState.BUSY)


def visual_status(snapshot: StatusSnapshot) -> VisualStatus:
    if snapshot.mode not in ("navigating", "mapping"):
        return VisualStatus.OFF
    status = _VISUAL.get(snapshot.localization_state, VisualStatus.UNINIT)
    if status is VisualStatus.TRACKING and snapshot.localization_quality < LOST_QUALITY:
        return VisualStatus.LOST
    return status


def charge_status(snapshot: StatusSnapshot, target: Target | None) -> ChargeStatus:
    """The local charging step: docking, finding the pile, on it, or failed at it."""
    if snapshot.charging:
        if snapshot.battery_percent >= CHARGED_PERCENT:
            return ChargeStatus.CHARGED
        return ChargeStatus.CHARGING
    active = snapshot.navigation_state in ("running", "paused")
    if snapshot.phase == "dock":
        if active:
            return ChargeStatus.DOCKING
        if snapshot.navigation_state == "failed":
            return ChargeStatus.ERROR
    if target is not None and target.index == CHARGE_PILE_INDEX:
        if active:
            return ChargeStatus.FINDING
        if snapshot.navigation_state == "failed":
            return ChargeStatus.ERROR
    return ChargeStatus.FREE


def target_fields(snapshot: StatusSnapshot, target: Target | None) -> dict[str, Any]:
    """``targetNumID``, ``targetStatus``, ``targetDistance``, ``angleGoalStatus``."""
    if snapshot.attempt_id is None or snapshot.navigation_state == "idle":
        return {"targetNumID": -1, "targetStatus": int(TargetStatus.INVALID),
                "targetDistance": -1.0, "angleGoalStatus": int(AngleGoalStatus.INVALID)}
    num_id = TARGET_WITHOUT_ID
    if target is not None and target.index >= 0:
        num_id = target.index
    status, angle = _TARGET.get(
        snapshot.navigation_state, (TargetStatus.INVALID, AngleGoalStatus.INVALID)
    )
    distance = -1.0
    if status in (TargetStatus.WORKING, TargetStatus.PAUSED):
        if snapshot.distance_remaining is not None:
            distance = float(snapshot.distance_remaining)
        elif snapshot.goal is not None:
            distance = math.hypot(snapshot.goal.x - snapshot.pose.x,
                                  snapshot.goal.y - snapshot.pose.y)
    elif snapshot.navigation_state == "succeeded":
        distance = 0.0
    return {"targetNumID": num_id, "targetStatus": int(status), "targetDistance": distance,
            "angleGoalStatus": int(angle)}


def galileo_status(ctx: Context, snapshot: StatusSnapshot | None = None) -> dict[str, Any]:
    """The GalileoStatus object (galileo-http-a §1.6), fields in the document's order."""
    snap = snapshot if snapshot is not None else ctx.runtime.status()
    objects.targets(ctx).update()
    target = ctx.target_of(snap.attempt_id)
    stamp = max(0.0, snap.stamp)
    secs = int(stamp)
    body: dict[str, Any] = {
        "header": {
            "seq": ctx.next_seq(),
            "stamp": {"secs": secs, "nsecs": min(999_999_999, int((stamp - secs) * 1e9))},
            "frame_id": "map",
        },
        "navStatus": int(NavStatus.OPENED if snap.mode == "navigating" else NavStatus.CLOSED),
        "visualStatus": int(visual_status(snap)),
        "mapStatus": int(MapStatus.MAPPING if snap.mode == "mapping" else MapStatus.NOT_MAPPING),
        "gcStatus": 0,
        "gbaStatus": int(GbaStatus.IDLE),
        "chargeStatus": int(charge_status(snap, target)),
        "loopStatus": int(
            LoopStatus.LOOPING if snap.patrol_state == "running" or looping(ctx)
            else LoopStatus.OFF
        ),
        "power": pack_voltage(ctx),
    }
    body.update(target_fields(snap, target))
    _native_marks(ctx, snap, body)
    body.update({
        "controlSpeedX": float(snap.linear),
        "controlSpeedTheta": float(snap.angular),
        "currentSpeedX": float(snap.linear),
        "currentSpeedTheta": float(snap.angular),
        "currentPosX": float(snap.pose.x),
        "currentPosY": float(snap.pose.y),
        "currentAngle": float(snap.pose.theta),
        "busyStatus": 1 if snap.mode == "busy" else 0,
    })
    return body


def _native_marks(ctx: Context, snap: StatusSnapshot, body: dict[str, Any]) -> None:
    """What the native commands add (:mod:`.native.marks`): a ``g n`` to no goal reads as
    error 3 until a newer goal starts; an angle command reports in ``angleGoalStatus``."""
    mark = marks(ctx)
    bad = mark.bad_goal_now(snap.attempt_id)
    if bad is not None:
        body.update({"targetNumID": bad, "targetStatus": int(TargetStatus.ERROR),
                     "targetDistance": -1.0, "angleGoalStatus": int(AngleGoalStatus.INVALID)})
        return
    angle_task = mark.angle_task_now(snap.attempt_id)
    if angle_task is None:
        return
    try:
        state = ctx.runtime.tasks.get(angle_task)["state"]
    except NotFound:
        mark.forget_angle_task(angle_task)
        return
    if state not in _RUNNING_TASK:
        mark.angle_task_ended(angle_task, snap.attempt_id)
    body["angleGoalStatus"] = int(_ANGLE.get(state, AngleGoalStatus.ERROR))


def looping(ctx: Context) -> bool:
    """Whether a Galileo loop task runs."""
    return objects.running(ctx, objects.LOOP) is not None


def pack_voltage(ctx: Context) -> float:
    """The supply voltage [V]; 0.0 when the robot cannot tell (powered off)."""
    try:
        return float(ctx.runtime.device.battery().voltage)
    except PolynavError as exc:
        log.debug("galileo: no battery reading: %s", exc)
        return 0.0


@ROUTES.get("/system/status", inline=True)
def get_system_status(ctx: Context, params: Params) -> Reply:
    """E-02: ``{"status": "Mapping" | "Navigating" | "Busy" | "Free"}``."""
    return {"status": system_state(ctx.runtime.status()).value}


@ROUTES.get("/system/galileo_status", inline=True)
def get_galileo_status(ctx: Context, params: Params) -> Reply:
    """E-04: the GalileoStatus object."""
    return galileo_status(ctx)
