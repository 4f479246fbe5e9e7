"""Runtime events to Yunji notifications (§3.10), sent to every connected client.

:data:`NOTIFICATIONS` catalogues every defined code; :data:`PRODUCED` are those polynav sends and
:data:`NOT_PRODUCED` those it has no feature for, each with the reason. ``data`` carries
``target`` (the move's marker, ``""`` for a location, §A-N2) for the move codes 01001-01027,
``distance`` travelled [m] when a move ends (01002/01003/01004, §3.10.3), and ``markers``,
``count``, ``distance_tolerance`` for the cruise codes 011xx; other codes carry ``{}``.

Sequences (§3.10.4): ``01001`` -> [``01010`` -> ``01011``] -> (``01005``)* -> [``01020`` ->
``01021``] -> ``01002``; a move that cannot plan from the start sends ``01007`` then ``01003``
with no retries; too many retries without progress send ``01006`` then ``01003``. ``01203``
(and ``01202`` when the robot stands on an obstacle or in a forbidden zone, ``01201`` when it
stands in unknown space or unknown space walls it in) is sent at most every 5 s of the runtime's
clock while planning keeps failing.
"""

from __future__ import annotations

import logging
from collections.abc import Callable

from polynav.protocols.yunji.messages import Notification
from polynav.runtime import events
from polynav.runtime.cart_events import CartAction, CartFailure, CartStep
from polynav.runtime.door_passage import (
    DoorControlFinished,
    DoorControlForced,
    DoorControlStarted,
)
from polynav.runtime.lift_events import HELD, LiftPhase, LiftPhaseChanged

log = logging.getLogger(__name__)

# code -> (level, description): every defined code of the spec's table (§3.10.1), verbatim
# (typos included, the stray quote of 04023 left out, §A-N6). Reserved codes are not here.
NOTIFICATIONS: dict[str, tuple[str, str]] = {
    "01001": ("info", "The move task is started."),
    "01002": ("info", "The move task is finished."),
    "01003": ("warning", "The move task is failed."),
    "01004": ("info", "The move task is canceled."),
    "01005": ("info", "The move task is retried."),
    "01006": ("warning", "The robot may be trapped."),
    "01007": ("warning", "Failed to find available path."),
    "01010": ("info", "Start to leave charging pile."),
    "01011": ("info", "Succeed to leave charging pile."),
    "01012": ("warning", "Failed to leave charging plie."),
    "01013": ("warning", "Leave charging pile retry."),
    "01020": ("info", "Start to auto dock to charging pile."),
    "01021": ("info", "Succced to auto dock to charging pile."),
    "01022": ("warning", "Failed to auto dock to charging pile."),
    "01023": ("warning", "Failed to to receive valid data."),
    "01024": ("warning", "Failed to find any feature around the robot."),
    "01025": ("warning", "Failed to catch power status."),
    "01026": ("warning", "Failed to catch infrared signal."),
    "01027": ("warning", "Failed to dock with timeout."),
    "01028": ("warning", "The cabin ID is wrong."),
    "01029": ("warning", "Failed to switch to lateral mode."),
    "01030": ("info", "Start controlling the electronic door."),
    "01031": ("info", "Finish controlling the electronic door."),
    "01032": ("warning", "Control the electronic door for too long, forced release control."),
    "01033": ("info", "congestion searched in narrow area, start waiting."),
    "01034": ("info", "no congestion, back to work."),
    "01050": ("info", "Start to leave container."),
    "01051": ("info", "Succeed to leave container."),
    "01052": ("warning", "Failed to leave container."),
    "01053": ("warning", "Leave container retry."),
    "01060": ("info", "Start to auto dock to container."),
    "01061": ("info", "Succeed to auto dock to container."),
    "01062": ("warning", "Failed to auto dock to container."),
    "01070": ("info", "Start to leave cabin."),
    "01071": ("info", "Succeed to leave cabin."),
    "01072": ("warning", "Failed to leave cabin."),
    "01073": ("warning", "Leave cabin retry."),
    "01080": ("info", "Start to auto dock to cabin."),
    "01081": ("info", "Succeed to auto dock to cabin."),
    "01082": ("warning", "Failed to auto dock to cabin."),
    "01101": ("info", "The cruise is started."),
    "01102": ("info", "The cruise is finished."),
    "01103": ("warning", "The cruise is failed."),
    "01104": ("info", "The cruise is canceled."),
    "01200": ("info", "Traffic is busy."),
    "01201": ("warning", "Trapped in unknown area."),
    "01202": ("warning", "Trapped in obstacle."),
    "01203": ("info", "Failed to make global plan."),
    "01204": ("info", "Failed to make local plan."),
    "01210": ("warning", "Detect no entry, zero velocity control."),
    "04000": ("info", "Start to go to lift."),
    "04001": ("info", "Succeed to go to lift."),
    "04002": ("info", "Failed to go to lift."),
    "04010": ("info", "Start to call lift."),
    "04011": ("info", "Succeed to call lift."),
    "04013": ("warning", "Call lift more than 3 minutes."),
    "04020": ("info", "Start to take lift."),
    "04021": ("info", "Succeed to take lift."),
    "04023": ("warning", "Take lift more than 3 minutes."),
    "04030": ("info", "Start to enter lift."),
    "04031": ("info", "Succeed to enter lift."),
    "04032": ("info", "Failed to enter lift."),
    "04033": ("info", "There is not enough space in the lift,take the next lift."),
    "04040": ("info", "Start to avoid liftt."),
    "04041": ("info", "Finish to avoid lift."),
    "04050": ("info", "Start to exit lift."),
    "04051": ("info", "Succeed to exit lift."),
    "04052": ("warning", "Failed to exit lift."),
    "04060": ("info", "Start to back to lift."),
    "04061": ("info", "Succeed to back to lift."),
    "04062": ("warning", "Failed to back to lift."),
    "04070": ("info", "Start waiting for the lift to unlock."),
    "04071": ("info", "End waiting for the lift to unlock."),
    "02000": ("info", "Poweroff notice."),
    "02001": ("info", "Charge status on."),
    "02002": ("info", "Charge status off."),
    "02003": ("info", "Estop on."),
    "02004": ("info", "Estop off."),
    "02005": ("warning", "Triggered attitude correction."),
    "02006": ("info", "Software shutdown notice."),
    "02010": ("warning", "The robot maybe lost."),
    "03001": ("warning", "Abnormal object was detected in the robot."),
}

# Codes whose trigger polynav has no feature for: catalogued, never sent (docs/yunji.md).
NOT_PRODUCED: dict[str, str] = {
    "01029": "polynav's bases (simulated and bridged) are differential: there is no lateral "
             "(sideways) mode to switch to, so the switch can neither be made nor fail "
             "(docs/decisions.md)",
}

# Codes the mapper below sends.
PRODUCED: frozenset[str] = frozenset({
    "01001", "01002", "01003", "01004", "01005", "01006", "01007",
    "01010", "01011", "01012", "01013", "01020", "01021", "01022", "01023", "01024", "01025",
    "01026", "01027", "01033", "01034",
    "01101", "01102", "01103", "01104",
    "01200", "01201", "01202", "01203", "01204", "01210",
    "02000", "02001", "02002", "02003", "02004", "02005", "02006", "02010",
    "03001",
    "04000", "04001", "04002", "04010", "04011", "04013", "04020", "04021", "04023",
    "04030", "04031", "04032", "04033", "04040", "04041", "04050", "04051", "04052", "04060",
    "04061", "04062", "04070", "04071",
    "01030", "01031", "01032",  # doors and gates on the way (runtime.door_passage)
    # Containers and cabins (runtime.cart_commands, protocols.yunji.containers).
    "01028", "01050", "01051", "01052", "01053", "01060", "01061", "01062",
    "01070", "01071", "01072", "01073", "01080", "01081", "01082",
})
# A dock or leave of a container (a cart) or a cabin: step -> code (§3.10.1 L656-L669).
_CART_CODES: dict[tuple[str, str, CartStep], str] = {
    ("leave", "cart", CartStep.STARTED): "01050",
    ("leave", "cart", CartStep.SUCCEEDED): "01051",
    ("leave", "cart", CartStep.FAILED): "01052",
    ("leave", "cart", CartStep.RETRIED): "01053",
    ("dock", "cart", CartStep.STARTED): "01060",
    ("dock", "cart", CartStep.SUCCEEDED): "01061",
    ("dock", "cart", CartStep.FAILED): "01062",
    ("leave", "cabin", CartStep.STARTED): "01070",
    ("leave", "cabin", CartStep.SUCCEEDED): "01071",
    ("leave", "cabin", CartStep.FAILED): "01072",
    ("leave", "cabin", CartStep.RETRIED): "01073",
    ("dock", "cabin", CartStep.STARTED): "01080",
    ("dock", "cabin", CartStep.SUCCEEDED): "01081",
    ("dock", "cabin", CartStep.FAILED): "01082",
}
PLANNING_NOTICE_PERIOD = 5.0  # [s] between repeats of 01201/01202/01203 (§3.10.1 L677)

_MOVE_END: dict[type[events.RuntimeEvent], str] = {
    events.NavigationSucceeded: "01002",
    events.NavigationFailed: "01003",
    events.NavigationCanceled: "01004",
}
# Move-task steps that carry only the target.
_STEP: dict[type[events.RuntimeEvent], str] = {
    events.ChargerLeaveStarted: "01010",
    events.ChargerLeft: "01011",
    events.ChargerLeaveFailed: "01012",
    events.ChargerLeaveRetry: "01013",
    events.DockingStarted: "01020",
    events.DockingSucceeded: "01021",
    events.NavigationBlocked: "01204",
    # People block the way and the robot waits for them: the same "no local plan" notice.
    events.NavigationWaiting: "01204",
}
_DOCK_CAUSE = {"bad_data": "01023", "no_feature": "01024", "no_contact": "01025",
               "no_infrared": "01026", "timeout": "01027"}
_PATROL: dict[type[events.RuntimeEvent], str] = {
    events.PatrolStarted: "01101",
    events.PatrolFinished: "01102",
    events.PatrolFailed: "01103",
    events.PatrolCanceled: "01104",
}
_STATUS: dict[type[events.RuntimeEvent], str] = {
    events.PowerOffNotice: "02000",
    events.RobotDisplaced: "02005",
    events.SoftwareShutdownNotice: "02006",
    events.ForeignObjectDetected: "03001",
    # The fleet's traffic rule (§3.10.1): a narrow passage held by another robot, the wait in
    # front of it and its end (data not covered by the spec, §A-N2: ``{}``).
    events.TrafficBusy: "01200",
    events.TrafficWaitStarted: "01033",
    events.TrafficWaitEnded: "01034",
    # A "no entry" sign spotted: the robot stops before it and plans round it or fails.
    events.NoEntrySignSeen: "01210",
}
# Retries that are the navigator's check of a first plan (clear the lidar marks, plan again),
# not a move retry: the move then either goes or fails with 01007 (no retries, L634).
_SILENT_RETRY_CAUSES = {"no path", "goal occupied"}
_UNREACHABLE_REASONS = {"no path", "goal occupied"}
# A precise goal reached where the scan could not confirm the pose: "maybe lost" (02010), then
# the move failure; Yunji has no code of its own for an arrival it cannot vouch for.
_NOT_LOCALIZED_REASONS = {"not localized"}
# Trapped: on an obstacle (01202); standing in unknown space, or walled in by it with
# unknown-as-obstacle on (01201).
_TRAPPED = {"start_occupied": "01202", "start_unknown": "01201", "walled_in_unknown": "01201"}


def _lift_detail(phase: LiftPhase, detail: str) -> list[str]:
    """The codes of a lift step that did not go as planned (``detail`` from the runtime)."""
    if detail == HELD:
        return ["04070"]
    if detail.startswith("back in: "):
        return ["04061"] if detail.endswith("succeeded") else ["04062"]
    if detail.startswith("avoided: "):
        return ["04041"]  # out of the car's way (or as far as it got): it tries again
    if phase is LiftPhase.EXITING:
        return ["04052", "04060"]  # blocked: back in, retry
    if phase is LiftPhase.ENTERING and "avoid" in detail:
        return ["04032", "04040"]  # blocked: out of the car's way, retry
    if "is full" in detail:
        return ["04033"]
    if "did not come within" in detail:
        return ["04013"]
    if "could not reach" in detail:
        return ["04002"]
    if phase is LiftPhase.ENTERING or "could not enter" in detail:
        return ["04032"]
    return []


def notification(code: str, data: dict[str, object] | None = None) -> Notification:
    level, description = NOTIFICATIONS[code]
    return Notification(code, level, description, data if data is not None else {})


class NotificationMapper:
    """Turns runtime events into notifications; keeps what it needs across events (the target
    of each attempt, the last combined e-stop state, when planning notices were last sent).

    Args:
        target_of: the marker name the adapter recorded for an attempt id, if any (moves sent
            as a pose built from a marker carry no point name in their events).
        estop_active: the combined e-stop state when mapping starts.
    """

    def __init__(self, target_of: Callable[[int], str | None], estop_active: bool) -> None:
        self._target_of = target_of
        self._targets: dict[int, str] = {}
        self._estop = estop_active
        self._lost = False
        self._planning_sent: dict[str, float] = {}
        self._lift_phase: dict[int, LiftPhase] = {}
        self._waited_unlock: set[int] = set()

    def _target(self, attempt_id: int) -> str:
        return self._targets.get(attempt_id) or self._target_of(attempt_id) or ""

    def map(self, event: events.RuntimeEvent) -> list[Notification]:
        if isinstance(event, events.NavigationStarted):
            target = event.point or self._target_of(event.attempt_id) or ""
            self._targets[event.attempt_id] = target
            self._planning_sent.clear()
            return [notification("01001", {"target": target})]
        if type(event) in _MOVE_END:
            return self._move_end(event)
        if type(event) in _STEP:
            assert isinstance(event, events.AttemptEvent | events.ChargerLeaveRetry
                              | events.NavigationBlocked | events.NavigationWaiting)
            return [notification(_STEP[type(event)], {"target": self._target(event.attempt_id)})]
        if isinstance(event, events.DockingFailed):
            data: dict[str, object] = {"target": self._target(event.attempt_id)}
            out = [notification("01022", data)]
            if event.cause in _DOCK_CAUSE:
                out.append(notification(_DOCK_CAUSE[event.cause], dict(data)))
            return out
        if isinstance(event, events.NavigationRetry):
            if event.cause in _SILENT_RETRY_CAUSES:
                return []
            return [notification("01005", {"target": self._target(event.attempt_id)})]
        if isinstance(event, events.PlanningFailed):
            return self._planning(event)
        if isinstance(event, events.PatrolEvent):
            return [notification(_PATROL[type(event)], {
                "markers": list(event.points),
                "count": event.count,
                "distance_tolerance": event.tolerance,
            })]
        if type(event) in _STATUS:
            return [notification(_STATUS[type(event)])]
        if isinstance(event, LiftPhaseChanged):
            return [notification(code) for code in self._lift(event)]
        if isinstance(event, DoorControlStarted | DoorControlFinished):
            # §3.10.4: passing a gate or electronic door, 01030 -> 01031 (with the move's
            # target, §A-N2 L1017), or 01032 when held too long and released by force.
            code = "01030" if isinstance(event, DoorControlStarted) else "01031"
            return [notification(code, {"target": self._target(event.attempt_id)})]
        if isinstance(event, DoorControlForced):
            return [notification("01032")]
        if isinstance(event, CartAction):
            # A wrong cabin id is told (01028) before the dock's failure (01082); a dock's
            # retry has no code of its own (only leaving has one, 01053/01073).
            wrong = ["01028"] if event.reason is CartFailure.WRONG_CABIN else []
            step = _CART_CODES.get((event.action, event.load, event.step))
            return [notification(c) for c in [*wrong, *([step] if step else [])]]
        return self._status(event)

    def _lift(self, event: LiftPhaseChanged) -> list[str]:
        """The 040xx codes of one step of the lift sequence (§3.10.4, L1034-L1040)."""
        phase, detail = event.phase, event.detail
        last = self._lift_phase.get(event.attempt_id)
        self._lift_phase[event.attempt_id] = phase
        if detail:
            if detail == HELD:
                self._waited_unlock.add(event.attempt_id)
            return _lift_detail(phase, detail)
        if phase is LiftPhase.GOING_TO_LIFT:
            return ["04000"]
        if phase is LiftPhase.WAITING_FOR_SESSION:
            return ["04001"]
        if phase is LiftPhase.CALLING:
            return (["04071"] if event.attempt_id in self._waited_unlock else []) + ["04010"]
        if phase is LiftPhase.ENTERING:
            return ["04011", "04030"] if last is LiftPhase.WAITING_FOR_CAR else ["04030"]
        if phase is LiftPhase.RIDING:
            return ["04031", "04020"]
        if phase is LiftPhase.SWITCHING_MAP:
            return ["04021"]
        if phase is LiftPhase.EXITING:
            return ["04050"]
        if phase is LiftPhase.LEFT:
            self._waited_unlock.discard(event.attempt_id)
            return ["04051"]
        return []

    def _move_end(self, event: events.RuntimeEvent) -> list[Notification]:
        assert isinstance(
            event,
            events.NavigationSucceeded | events.NavigationFailed | events.NavigationCanceled,
        )
        target = self._targets.pop(event.attempt_id, "") or (
            self._target_of(event.attempt_id) or ""
        )
        out: list[Notification] = []
        self._lift_phase.pop(event.attempt_id, None)
        self._waited_unlock.discard(event.attempt_id)
        if isinstance(event, events.NavigationFailed):
            if "did not arrive within" in event.reason:
                out.append(notification("04023"))
            if event.reason in _NOT_LOCALIZED_REASONS:
                out.append(notification("02010"))
            if event.reason == "stuck":
                out.append(notification("01006", {"target": target}))
            elif event.reason in _UNREACHABLE_REASONS and not event.planned:
                out.append(notification("01007", {"target": target}))
        data: dict[str, object] = {"target": target, "distance": float(event.distance)}
        out.append(notification(_MOVE_END[type(event)], data))
        return out

    def _planning(self, event: events.PlanningFailed) -> list[Notification]:
        out: list[Notification] = []
        for code in (_TRAPPED.get(event.cause), "01203"):
            if code is None:
                continue
            last = self._planning_sent.get(code)
            if last is None or event.stamp - last >= PLANNING_NOTICE_PERIOD - 1e-9:
                self._planning_sent[code] = event.stamp
                out.append(notification(code))
        return out

    def _status(self, event: events.RuntimeEvent) -> list[Notification]:
        if isinstance(event, events.EStopChanged) and event.active != self._estop:
            self._estop = event.active
            return [notification("02003" if event.active else "02004")]
        if isinstance(event, events.ChargeChanged):
            return [notification("02001" if event.charging else "02002")]
        if isinstance(event, events.LocalizationChanged):
            lost = event.state == "lost"
            changed, self._lost = lost != self._lost, lost
            if lost and changed:
                return [notification("02010")]
        return []
