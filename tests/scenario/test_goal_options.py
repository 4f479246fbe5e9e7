"""Per-goal options and the charger phases, through the runtime on the seeded demo site.

A charger point is docked onto (charging contact is the simulator's: standing still on the
charger's pose); a robot on its charger backs off before it plans. Simulated time throughout.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from pathlib import Path

import pytest

from polynav.api.schemas import StatusOut
from polynav.errors import Conflict, InvalidRequest, NotFound
from polynav.geometry import Pose2D, angle_diff
from polynav.nav.attempt import GoalOptions
from polynav.runtime import events
from polynav.runtime.event_bus import Subscription
from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.site import Point, PointKind
from polynav.store.site_store import SiteStore
from polynav.tasks.patrol import PatrolPlan
from polynav.worlds.world import World


@pytest.fixture
def runtime(world: World, tmp_path: Path) -> Iterator[RobotRuntime]:
    with SiteStore.open(tmp_path / "data", seed_world=world) as store:
        rt = RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False))
        rt.start_navigation("floor1")
        rt.advance(0.5)
        yield rt


def _run(rt: RobotRuntime, timeout: float = 120.0) -> str:
    assert rt.advance_until(lambda: rt.status().navigation_state != "running", timeout)
    return rt.status().navigation_state


def _kinds(sub: Subscription, wanted: set[str]) -> list[str]:
    return [e.kind for e in sub.get_nowait() if e.kind in wanted]


CHARGER_KINDS = {
    "navigation_started", "navigation_succeeded", "navigation_failed", "docking_started",
    "docking_succeeded", "docking_failed", "charger_leave_started", "charger_leave_retry",
    "charger_left", "charger_leave_failed", "charge_changed",
}


def _dock(rt: RobotRuntime) -> None:
    rt.go_to(point="charger")
    assert _run(rt) == "succeeded"
    rt.advance(0.5)
    assert rt.status().charging


def test_a_charger_point_is_docked_onto_and_charging_starts(runtime: RobotRuntime) -> None:
    sub = runtime.bus.subscribe()
    runtime.go_to(point="charger")
    assert runtime.advance_until(lambda: runtime.status().phase == "dock", 120.0)
    assert runtime.status().navigation_state == "running"  # docking is part of the move
    shown = StatusOut.model_validate(runtime.status().to_dict())  # as GET /api/status shows it
    assert (shown.navigation.phase, shown.navigation.state) == ("dock", "running")
    assert _run(runtime) == "succeeded"
    runtime.advance(0.5)
    assert runtime.status().charging
    charger = runtime.store.point("floor1", "charger").pose
    true = runtime.simulation.true_pose
    assert true.distance_to(charger) <= 0.1
    assert _kinds(sub, CHARGER_KINDS) == [
        "navigation_started", "docking_started", "docking_succeeded", "navigation_succeeded",
        "charge_changed",
    ]


def test_a_move_from_the_charger_backs_off_it_first(runtime: RobotRuntime) -> None:
    _dock(runtime)
    sub = runtime.bus.subscribe()
    runtime.go_to(point="lobby")
    runtime.advance(0.1)
    assert runtime.status().phase == "leave_charger"
    assert _run(runtime) == "succeeded"
    assert _kinds(sub, CHARGER_KINDS) == [
        "navigation_started", "charger_leave_started", "charge_changed", "charger_left",
        "navigation_succeeded",
    ]


def test_leaving_the_charger_retries_every_10_s_then_fails(runtime: RobotRuntime) -> None:
    _dock(runtime)
    sub = runtime.bus.subscribe()
    runtime.set_software_estop(True)
    runtime.go_to(point="lobby")
    assert _run(runtime, timeout=60.0) == "failed"
    assert runtime.status().reason == "undock failed"
    seen = [e for e in sub.get_nowait() if e.kind in CHARGER_KINDS]
    assert [e.kind for e in seen] == [
        "navigation_started", "charger_leave_started", "charger_leave_retry",
        "charger_leave_retry", "charger_leave_retry", "charger_leave_failed", "navigation_failed",
    ]
    retries = [e for e in seen if isinstance(e, events.ChargerLeaveRetry)]
    assert [e.retries for e in retries] == [1, 2, 3]
    gaps = [b.stamp - a.stamp for a, b in zip(seen[1:5], seen[2:6], strict=True)]
    assert all(abs(gap - 10.0) < 0.1 for gap in gaps), gaps


def test_docking_where_no_charger_stands_fails_having_seen_none(
    runtime: RobotRuntime,
) -> None:
    runtime.store.add_point(
        Point("fake_dock", "floor1", Pose2D(5.5, 12.5, math.pi), PointKind.CHARGER, 40)
    )
    sub = runtime.bus.subscribe()
    runtime.go_to(point="fake_dock")
    assert _run(runtime) == "failed"
    assert runtime.status().reason == "dock failed"
    failed = [e for e in sub.get_nowait() if isinstance(e, events.DockingFailed)]
    assert [e.cause for e in failed] == ["no_feature"]  # the robot looked, and saw no plate
    assert not runtime.status().charging


def test_heading_tolerance_and_reversed_heading_are_per_goal(runtime: RobotRuntime) -> None:
    lobby = runtime.store.point("floor1", "lobby").pose
    flipped = Pose2D(lobby.x, lobby.y, math.pi)
    runtime.go_to(pose=flipped, options=GoalOptions(reverse_allowed=True))
    assert _run(runtime) == "succeeded"
    true = runtime.simulation.true_pose
    # Arrived facing east (0 rad), which the reversed heading accepts.
    assert min(abs(angle_diff(true.theta, 0.0)), abs(angle_diff(true.theta, math.pi))) <= 0.1
    assert true.distance_to(flipped) <= 0.1
    runtime.go_to(pose=Pose2D(8.0, 8.5, 0.0), options=GoalOptions(yaw_tolerance=0.6))
    assert _run(runtime) == "succeeded"
    assert abs(angle_diff(runtime.simulation.true_pose.theta, 0.0)) <= 0.6


def test_an_occupied_goal_within_near_tolerance_ends_next_to_it(runtime: RobotRuntime) -> None:
    wall = Pose2D(0.2, 12.5, math.pi)  # inside the west wall by the lobby
    runtime.go_to(pose=wall)
    assert _run(runtime) == "failed"
    runtime.go_to(pose=wall, options=GoalOptions(near_tolerance=1.0))
    assert _run(runtime) == "succeeded"
    assert runtime.simulation.true_pose.distance_to(wall) <= 1.0


def test_max_retries_is_per_goal(runtime: RobotRuntime) -> None:
    sub = runtime.bus.subscribe()
    runtime.go_to(pose=Pose2D(0.2, 12.5, 0.0), options=GoalOptions(max_retries=0))
    assert _run(runtime) == "failed"
    assert runtime.status().retries <= 1
    assert any(isinstance(e, events.PlanningFailed) for e in sub.get_nowait())


PATROL_KINDS = {
    "patrol_started", "patrol_finished", "patrol_failed", "patrol_canceled",
    "navigation_started", "navigation_succeeded", "navigation_failed", "navigation_canceled",
}


def _patrol_log(sub: Subscription) -> list[tuple[str, str | None]]:
    out: list[tuple[str, str | None]] = []
    for e in sub.get_nowait():
        if e.kind in PATROL_KINDS:
            out.append((e.kind, e.point if isinstance(e, events.NavigationStarted) else None))
    return out


def test_a_patrol_visits_its_points_round_after_round(runtime: RobotRuntime) -> None:
    sub = runtime.bus.subscribe()
    runtime.patrol(PatrolPlan(("lobby", "front_desk", "corridor_west"), count=2, tolerance=0.5))
    assert runtime.status().patrol_state == "running"
    assert runtime.advance_until(lambda: runtime.status().patrol_state != "running", 300.0)
    assert runtime.status().patrol_state == "succeeded"
    legs = ["lobby", "front_desk", "corridor_west"] * 2
    assert _patrol_log(sub) == [
        ("patrol_started", None),
        *[pair for leg in legs for pair in (("navigation_started", leg),
                                              ("navigation_succeeded", None))],
        ("patrol_finished", None),
    ]
    last = runtime.store.point("floor1", "corridor_west").pose
    assert runtime.simulation.true_pose.distance_to(last) <= 0.5


def test_a_patrol_skips_a_failed_leg_and_fails_if_the_last_leg_fails(
    runtime: RobotRuntime,
) -> None:
    wall = Pose2D(0.2, 12.5, 0.0)
    runtime.store.add_point(Point("in_wall", "floor1", wall, PointKind.GENERAL, 41))
    sub = runtime.bus.subscribe()
    runtime.patrol(PatrolPlan(("in_wall", "lobby", "in_wall"), count=1))
    assert runtime.advance_until(lambda: runtime.status().patrol_state != "running", 300.0)
    assert runtime.status().patrol_state == "failed"
    kinds = [kind for kind, _ in _patrol_log(sub)]
    assert kinds == [
        "patrol_started", "navigation_started", "navigation_failed", "navigation_started",
        "navigation_succeeded", "navigation_started", "navigation_failed", "patrol_failed",
    ]


def test_canceling_a_patrol_ends_it_and_a_new_goal_replaces_it(runtime: RobotRuntime) -> None:
    runtime.patrol(PatrolPlan(("lobby", "front_desk"), count=-1))
    runtime.advance(3.0)
    sub = runtime.bus.subscribe()
    runtime.cancel()
    assert runtime.status().patrol_state == "canceled"
    assert [kind for kind, _ in _patrol_log(sub)] == ["navigation_canceled", "patrol_canceled"]
    with pytest.raises(Conflict):
        runtime.cancel()
    runtime.go_to(point="lobby")
    assert runtime.status().patrol_state is None
    with pytest.raises(InvalidRequest):
        PatrolPlan(("lobby",))
    with pytest.raises(NotFound):
        runtime.patrol(PatrolPlan(("lobby", "nowhere")))
    assert runtime.status().navigation_state == "running"  # the refused patrol changed nothing
