"""One cross-map goal being run: its legs, where it stands, and how the status shows it.

:class:`RouteRun` is the lift sequence's memory (:mod:`polynav.runtime.lift_commands` moves it
on each control tick); :func:`status_dict` is the ``route`` object of ``GET /api/status``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

from polynav.geometry import Pose2D
from polynav.nav.attempt import GoalOptions, NavigationState
from polynav.routing.route import DriveLeg, Leg, LiftLeg, SwitchLeg
from polynav.runtime.events import pose_dict
from polynav.runtime.lift_events import LiftPhase
from polynav.runtime.status import StatusSnapshot

CALL_TIMEOUT = 180.0
"""A car that has not stood open at the robot's floor this long [s] after the call is given up
(issue 11: call > 3 min)."""
RIDE_TIMEOUT = 180.0
"""A ride that has not arrived this long [s] after the doors were asked to close fails."""
SESSION_TIMEOUT = 600.0
"""A car's session not granted within this [s] (other robots kept it) is given up."""
MAX_DOOR_RETRIES = 3
"""Entering or leaving a car blocked this many times gives that car up (or the route)."""
MAX_REQUEUES = 2
"""How often a goal queues again for the cars it gave up for a passing cause (busy, full, door
blocked) when no other car serves; then it fails with the router's reason."""
RETRY_PAUSE = 3.0
"""Wait [s] before driving through a blocked car door again."""
AT_POINT = 0.3
"""Within this [m] of the outside point the robot need not drive there before entering."""


@dataclass(slots=True)
class RouteRun:
    """A running (or the last) cross-map goal.

    Attributes:
        attempt_id: its runtime id (one attempt to callers, whatever its legs).
        goal, goal_map, goal_point: where it ends.
        options: the goal options of its last leg.
        legs: the current route's legs; ``index`` the one running.
        state: running, or how it ended; ``reason`` why it failed.
        nav_id: the navigator's id of the leg goal running now, if any.
        phase: the lift sequence's phase while in a lift leg (or going to one).
        car: the car whose session this robot asked for or holds.
        excluded: cars given up during this goal (full, blocked, did not come).
        requeues: how often the goal queued again for cars it had given up.
        faulty: given-up cars never queued for again (called, they did not come).
        since: when the current phase began [s]; ``retries`` door retries in it.
        resume_at: a retry waits until then [s].
        backing_in: leaving the car failed; the robot drives back in before trying again.
        avoiding: entering the car failed; the robot gets out of the car's way (back to its
            outside point) before trying again.
        distance: metres driven by finished legs.
    """

    attempt_id: int
    goal: Pose2D
    goal_map: str
    goal_point: str | None
    options: GoalOptions
    legs: list[Leg]
    started_at: float
    index: int = 0
    state: NavigationState = NavigationState.RUNNING
    reason: str | None = None
    nav_id: int | None = None
    phase: LiftPhase | None = None
    car: str | None = None
    excluded: set[str] = field(default_factory=set)
    requeues: int = 0
    faulty: set[str] = field(default_factory=set)
    since: float = 0.0
    retries: int = 0
    resume_at: float = 0.0
    backing_in: bool = False
    avoiding: bool = False
    called: bool = False
    announced_wait: bool = False
    wait_started: float | None = None
    distance: float = 0.0
    ended_at: float | None = None

    @property
    def leg(self) -> Leg:
        return self.legs[self.index]

    @property
    def next_leg(self) -> Leg | None:
        return self.legs[self.index + 1] if self.index + 1 < len(self.legs) else None

    def next_leg_lift(self) -> LiftLeg | None:
        leg = self.next_leg
        return leg if isinstance(leg, LiftLeg) else None

    def advance(self, now: float) -> None:
        """On to the next leg, with its phase state cleared."""
        self.index += 1
        self.nav_id = None
        self.phase = None
        self.since = now
        self.retries = 0
        self.backing_in = False
        self.avoiding = False
        self.called = False
        self.announced_wait = False


NEAR_LIFT = 4.0
"""A robot this close [m] to a car's door that cannot reach its waiting spot waits where it is."""

NEAR_LIFT_OPTIONS = GoalOptions(near_tolerance=1.5)
"""Going to a lift (its waiting spot or door): another robot may stand on the spot; ending near
it will do."""

AT_DOOR = GoalOptions(near_tolerance=0.3, max_retries=4)
"""To the door once the car is this robot's: on the spot, or next to it. The sequence tries
this leg again itself (then queues again or takes another car), so the leg keeps the plain
retry limit and closes no passages (:mod:`polynav.nav.passages`): a blocked door is reported
in the time the sequence's retries expect, not after a minute of going round."""

IN_CAR = GoalOptions(yaw_tolerance=0.3, max_retries=1, goal_wait=0.0)
"""Goals into and out of a car: a loose heading (the car is small), one retry and no wait for
an occupied spot, so that a blocked door or a full car is reported to the sequence (which
retries after a pause, or takes the next car) rather than fought or waited out."""

OUT_OF_CAR = GoalOptions(pass_tolerance=0.5, max_retries=1, goal_wait=0.0)
"""Out of a car to its outside point: out once past it, with no stop or turn there (the next
leg drives on; a stop and a half turn on the spot kept the car from its next user 4 s longer)."""


def carried(pose: Pose2D, inside_from: Pose2D, inside_to: Pose2D) -> Pose2D:
    """The robot's pose on the new floor: where it stands relative to the car's inside point,
    applied to the inside point of the new floor (the lift's known position)."""
    dx, dy = pose.x - inside_from.x, pose.y - inside_from.y
    turn = inside_to.theta - inside_from.theta
    c, s = math.cos(turn), math.sin(turn)
    return Pose2D(inside_to.x + c * dx - s * dy, inside_to.y + s * dx + c * dy,
                  math.atan2(math.sin(pose.theta + turn), math.cos(pose.theta + turn)))


def overlay(snapshot: StatusSnapshot, run: RouteRun) -> StatusSnapshot:
    """``snapshot`` as callers see the cross-map goal ``run``: its id, goal and state, the
    phase of a leg's goal (``navigate`` between them) and the ``route``."""
    state = run.state.value
    if run.state is NavigationState.RUNNING and snapshot.navigation_state == "paused" and (
            run.nav_id is not None):
        state = "paused"
    return replace(
        snapshot, navigation_state=state, attempt_id=run.attempt_id, goal=run.goal,
        goal_point=run.goal_point, reason=run.reason,
        phase=snapshot.phase if run.nav_id is not None and snapshot.phase else "navigate",
        distance_remaining=snapshot.distance_remaining if run.index == len(run.legs) - 1
        else None, route=status_dict(run))


def leg_dict(leg: Leg) -> dict[str, object]:
    """One leg as JSON."""
    if isinstance(leg, DriveLeg):
        return {"kind": "drive", "map": leg.map_name, "point": leg.point,
                "goal": pose_dict(leg.goal)}
    if isinstance(leg, LiftLeg):
        return {"kind": "lift", "car": leg.car, "from_floor": leg.from_floor,
                "from_map": leg.from_map, "to_floor": leg.to_floor, "to_map": leg.to_map}
    assert isinstance(leg, SwitchLeg)
    return {"kind": "switch", "from_map": leg.from_map, "to_map": leg.to_map,
            "point": leg.to_point}


def status_dict(run: RouteRun) -> dict[str, object]:
    """The status's ``route``: the goal's map, the legs, the running one and the lift phase."""
    lift: dict[str, object] | None = None
    leg = run.leg if run.index < len(run.legs) else None
    target = leg if isinstance(leg, LiftLeg) else run.next_leg_lift()
    if run.phase is not None and target is not None:
        lift = {"car": target.car, "phase": run.phase.value, "from_floor": target.from_floor,
                "to_floor": target.to_floor,
                "manoeuvre": "avoiding" if run.avoiding else
                             "backing_in" if run.backing_in else None}
    return {
        "goal_map": run.goal_map,
        "legs": [leg_dict(leg) for leg in run.legs],
        "current_leg": min(run.index, len(run.legs) - 1),
        "lift": lift,
        "excluded_cars": sorted(run.excluded),
    }
