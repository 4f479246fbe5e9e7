"""The runtime on the simulated demo site, on simulated time (advance), judged on ground truth."""

from __future__ import annotations

import dataclasses
import math
import threading
from pathlib import Path

import pytest

from polynav.errors import Conflict, InvalidRequest, NotFound
from polynav.geometry import Pose2D, angle_diff
from polynav.maps.keepout import VirtualWall
from polynav.runtime import events
from polynav.runtime.event_bus import Subscription
from polynav.runtime.robot_runtime import Mode, RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds.world import World

POSITION_TOLERANCE = 0.1
HEADING_TOLERANCE = 0.1


@pytest.fixture
def runtime(world: World, store: SiteStore) -> RobotRuntime:
    return RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False))


def _kinds(sub: Subscription) -> list[str]:
    return [e.kind for e in sub.get_nowait()]


def _navigating(runtime: RobotRuntime) -> None:
    runtime.start_navigation("floor1")
    runtime.advance(0.5)


def _finished(runtime: RobotRuntime) -> bool:
    return runtime.status().navigation_state in ("succeeded", "failed", "canceled")


def test_start_navigation_passes_through_busy_and_localizes(runtime: RobotRuntime) -> None:
    sub = runtime.bus.subscribe()
    assert runtime.mode is Mode.FREE
    runtime.start_navigation("floor1")
    runtime.advance(0.5)
    got = sub.get_nowait()
    assert [e.kind for e in got] == [
        "mode_changed", "pose_initialized", "mode_changed", "localization_changed"]
    assert (got[0].old, got[0].new) == ("free", "busy")  # type: ignore[attr-defined]
    assert (got[2].old, got[2].new) == ("busy", "navigating")  # type: ignore[attr-defined]
    assert got[3].state == "tracking"  # type: ignore[attr-defined]
    status = runtime.status()
    assert (status.mode, status.map, status.floor) == ("navigating", "floor1", "floor1")
    assert status.localization_state == "tracking"


def test_go_to_a_point_succeeds_with_events_in_order(runtime: RobotRuntime, world: World) -> None:
    _navigating(runtime)
    sub = runtime.bus.subscribe()
    attempt_id = runtime.go_to(point="lobby")
    assert runtime.advance_until(lambda: _finished(runtime), timeout=120.0)
    got = [e for e in sub.get_nowait() if e.kind.startswith("navigation")]
    assert [e.kind for e in got] == ["navigation_started", "navigation_succeeded"]
    started, succeeded = got
    goal = world.floor("floor1").point("lobby").pose
    assert started == events.NavigationStarted(started.stamp, attempt_id, goal, "lobby")
    assert succeeded.attempt_id == attempt_id  # type: ignore[attr-defined]
    assert succeeded.distance > 4.0  # type: ignore[attr-defined]
    status = runtime.status()
    assert status.navigation_state == "succeeded"
    assert (status.goal, status.goal_point, status.attempt_id) == (goal, "lobby", attempt_id)
    for pose in (runtime.simulation.true_pose, status.pose):
        assert pose.distance_to(goal) <= POSITION_TOLERANCE, pose
        assert abs(pose.heading_error_to(goal)) <= HEADING_TOLERANCE, pose


def test_attempt_ids_keep_counting(runtime: RobotRuntime) -> None:
    _navigating(runtime)
    first = runtime.go_to(point="lobby")
    second = runtime.go_to(pose=Pose2D(8.0, 8.5, 0.0))
    runtime.update_settings({"max_linear_velocity": 0.5})
    runtime.cancel()
    third = runtime.go_to(point="lobby")
    assert (first, second, third) == (1, 2, 3)


def test_cancel_mid_way_ends_canceled_and_the_base_stops(runtime: RobotRuntime) -> None:
    _navigating(runtime)
    sub = runtime.bus.subscribe()
    attempt_id = runtime.go_to(point="office_1")
    runtime.advance(6.0)
    assert runtime.simulation.true_twist.linear > 0.1
    runtime.cancel()
    runtime.advance(1.0)
    got = [e for e in sub.get_nowait() if e.kind.startswith("navigation")]
    assert [e.kind for e in got] == ["navigation_started", "navigation_canceled"]
    assert got[1].attempt_id == attempt_id  # type: ignore[attr-defined]
    assert got[1].distance > 1.0  # type: ignore[attr-defined]
    assert runtime.status().navigation_state == "canceled"
    assert runtime.simulation.true_twist.linear == 0.0
    with pytest.raises(Conflict):
        runtime.cancel()


def test_pause_holds_the_robot_and_resume_reaches_the_goal(runtime: RobotRuntime) -> None:
    _navigating(runtime)
    sub = runtime.bus.subscribe()
    runtime.go_to(point="lobby")
    runtime.advance(4.0)
    with pytest.raises(Conflict):
        runtime.resume()
    runtime.pause()
    runtime.advance(1.0)
    held = runtime.simulation.true_pose
    runtime.advance(2.0)
    assert runtime.simulation.true_pose.distance_to(held) == 0.0
    assert runtime.status().navigation_state == "paused"
    with pytest.raises(Conflict):
        runtime.pause()
    runtime.resume()
    assert runtime.advance_until(lambda: _finished(runtime), timeout=120.0)
    assert [k for k in _kinds(sub) if k.startswith("navigation")] == [
        "navigation_started", "navigation_paused", "navigation_resumed", "navigation_succeeded"]


def test_goal_errors(runtime: RobotRuntime) -> None:
    with pytest.raises(Conflict):
        runtime.go_to(point="lobby")
    with pytest.raises(NotFound):
        runtime.start_navigation("floor9")
    with pytest.raises(NotFound):
        runtime.start_navigation("floor1", point="nowhere")
    assert runtime.mode is Mode.FREE
    _navigating(runtime)
    with pytest.raises(NotFound):
        runtime.go_to(point="nowhere")
    with pytest.raises(NotFound):
        runtime.go_to(point="lounge", map_name="floor9")  # another map is routed, if it exists
    with pytest.raises(InvalidRequest):
        runtime.go_to()
    with pytest.raises(InvalidRequest):
        runtime.go_to(point="lobby", pose=Pose2D())
    assert runtime.status().navigation_state == "idle"


def test_stop_navigation_cancels_the_goal_and_returns_to_free(runtime: RobotRuntime) -> None:
    _navigating(runtime)
    runtime.go_to(point="office_1")
    runtime.advance(2.0)
    sub = runtime.bus.subscribe()
    runtime.stop_navigation()
    got = sub.get_nowait()
    assert [e.kind for e in got] == [
        "mode_changed", "navigation_canceled", "mode_changed", "localization_changed"]
    assert [(e.old, e.new) for e in got if isinstance(e, events.ModeChanged)] == [
        ("navigating", "busy"), ("busy", "free")]
    status = runtime.status()
    assert (status.mode, status.map, status.navigation_state) == ("free", None, "canceled")
    runtime.stop_navigation()  # already free: nothing happens
    assert sub.get_nowait() == []
    with pytest.raises(Conflict):
        runtime.set_initial_pose(Pose2D(8.0, 8.5, 0.0))


def test_start_navigation_on_another_floor_moves_the_simulated_robot_there(
    runtime: RobotRuntime, world: World
) -> None:
    runtime.start_navigation("floor2")
    runtime.advance(1.0)
    initial = world.floor("floor2").point("initial").pose
    status = runtime.status()
    assert (status.floor, status.map, status.localization_state) == (
        "floor2", "floor2", "tracking")
    assert runtime.simulation.true_pose == initial
    assert status.pose.distance_to(initial) < POSITION_TOLERANCE


def test_set_initial_pose_restarts_localization(runtime: RobotRuntime) -> None:
    _navigating(runtime)
    sub = runtime.bus.subscribe()
    runtime.set_initial_pose(Pose2D(8.2, 8.4, 0.1))
    runtime.advance(1.0)
    kinds = _kinds(sub)
    assert kinds[0] == "pose_initialized"
    assert "localization_changed" in kinds
    assert runtime.status().localization_state == "tracking"
    assert runtime.status().pose.distance_to(Pose2D(8.0, 8.5)) < POSITION_TOLERANCE


def test_teleop_dead_man_stops_the_base_after_silence(runtime: RobotRuntime) -> None:
    sim = runtime.simulation
    runtime.teleop(0.4, 0.0)
    sent = runtime.now()
    runtime.advance(0.4)
    speed = sim.true_twist.linear
    assert speed > 0.3
    # Silence: the command holds until the timeout, then the base brakes.
    assert runtime.advance_until(lambda: sim.true_twist.linear < speed, timeout=1.0)
    braking_from = runtime.now() - sent
    assert 0.5 - 0.021 <= braking_from <= 0.5 + 0.021
    braking = speed / sim.config.linear_deceleration
    assert runtime.advance_until(lambda: sim.true_twist.linear == 0.0, timeout=braking + 0.05)
    assert runtime.now() - sent <= 0.5 + braking + 0.05


def test_teleop_repeated_every_200_ms_keeps_moving(runtime: RobotRuntime) -> None:
    sim = runtime.simulation
    runtime.teleop(0.3, 0.0)
    runtime.advance(0.5)
    slowest = math.inf
    for _ in range(10):
        runtime.teleop(0.3, 0.0)
        for _ in range(10):
            runtime.advance(0.02)
            slowest = min(slowest, sim.true_twist.linear)
    assert slowest == pytest.approx(0.3)
    assert sim.collisions == []


def test_teleop_is_clamped_to_the_speed_settings(runtime: RobotRuntime) -> None:
    runtime.update_settings({"max_angular_velocity": 0.5})
    runtime.teleop(0.0, 3.0)
    runtime.advance(0.4)
    assert runtime.simulation.true_twist.angular == pytest.approx(0.5)
    with pytest.raises(InvalidRequest):
        runtime.teleop(math.nan, 0.0)


def test_teleop_is_refused_while_a_goal_runs(runtime: RobotRuntime) -> None:
    _navigating(runtime)
    runtime.go_to(point="lobby")
    with pytest.raises(Conflict):
        runtime.teleop(0.2, 0.0)
    with pytest.raises(Conflict):
        runtime.local_move(rotate=1.0)


def test_software_estop_stops_the_base_and_publishes_on_and_off(runtime: RobotRuntime) -> None:
    sim = runtime.simulation
    sub = runtime.bus.subscribe()
    runtime.teleop(0.0, 1.0)
    runtime.advance(0.3)
    assert sim.true_twist.angular > 0.5
    runtime.set_software_estop(True)
    runtime.advance(0.3)
    assert sim.true_twist.angular == 0.0
    assert runtime.status().estop_software
    with pytest.raises(Conflict):
        runtime.teleop(0.0, 1.0)
    runtime.set_software_estop(False)
    runtime.advance(0.1)
    sim.press_estop()
    runtime.advance(0.1)
    got = [e for e in sub.get_nowait() if isinstance(e, events.EStopChanged)]
    assert [(e.hardware, e.software, e.active) for e in got] == [
        (False, True, True), (False, False, False), (True, False, True)]
    assert runtime.status().estop_hardware


def test_software_estop_holds_a_goal_until_released(runtime: RobotRuntime) -> None:
    _navigating(runtime)
    runtime.go_to(point="lobby")
    runtime.advance(3.0)
    runtime.set_software_estop(True)
    runtime.advance(1.0)
    held = runtime.simulation.true_pose
    runtime.advance(2.0)
    assert runtime.simulation.true_pose == held
    assert runtime.status().navigation_state == "running"
    runtime.set_software_estop(False)
    assert runtime.advance_until(lambda: _finished(runtime), timeout=120.0)
    assert runtime.status().navigation_state == "succeeded"


def test_out_of_range_setting_is_refused_and_not_stored(runtime: RobotRuntime) -> None:
    with pytest.raises(InvalidRequest) as info:
        runtime.update_settings({"max_linear_velocity": 5.0})
    assert info.value.field == "max_linear_velocity"
    assert runtime.store.settings() == {}
    assert runtime.settings().max_linear_velocity == 0.6


def test_lowered_max_speed_holds_on_the_next_goal(runtime: RobotRuntime) -> None:
    _navigating(runtime)
    new = runtime.update_settings({"max_linear_velocity": 0.3})
    assert new.max_linear_velocity == 0.3
    assert runtime.settings() == new
    assert runtime.store.settings() == {"max_linear_velocity": 0.3}
    sim = runtime.simulation
    fastest = 0.0

    def done() -> bool:
        nonlocal fastest
        fastest = max(fastest, sim.true_twist.linear)
        return _finished(runtime)

    runtime.go_to(point="front_desk")
    assert runtime.advance_until(done, timeout=120.0)
    assert runtime.status().navigation_state == "succeeded"
    assert 0.25 < fastest <= 0.3 + 1e-9


def test_settings_persist_across_a_restart(world: World, tmp_path: Path) -> None:
    with SiteStore.open(tmp_path / "site", seed_world=world) as store:
        first = RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False))
        first.update_settings({"robot_radius": 0.3})
    with SiteStore.open(tmp_path / "site") as store:
        second = RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False))
        assert second.settings().robot_radius == 0.3


def test_local_move_stops_short_of_a_virtual_wall_from_the_store(
    runtime: RobotRuntime, store: SiteStore
) -> None:
    # Without the wall the robot drives on to x = 9.5 (a real wall stops it there).
    store.set_keepouts("floor1", [VirtualWall(((9.0, 7.5), (9.0, 9.5)))])
    _navigating(runtime)
    sim = runtime.simulation
    runtime.local_move(distance=3.0)
    runtime.advance(10.0)
    assert sim.true_twist.linear == 0.0
    assert 8.2 < sim.true_pose.x < 9.0 - 0.25


def test_low_battery_event_once_per_crossing(runtime: RobotRuntime) -> None:
    sub = runtime.bus.subscribe()
    runtime.update_settings({"low_battery_percent": 85.0})
    runtime.advance(2.0)
    lows = [e for e in sub.get_nowait() if isinstance(e, events.LowBattery)]
    assert len(lows) == 1
    assert lows[0].percent == pytest.approx(80.0, abs=0.01)


def test_docking_on_the_charger_publishes_charging(runtime: RobotRuntime) -> None:
    _navigating(runtime)
    sub = runtime.bus.subscribe()
    runtime.go_to(point="charger")
    assert runtime.advance_until(lambda: runtime.status().charging, timeout=120.0)
    charges = [e for e in sub.get_nowait() if isinstance(e, events.ChargeChanged)]
    assert [e.charging for e in charges] == [True]
    runtime.local_move(distance=-0.3)  # back off: the charger's plate is in front
    runtime.advance(3.0)
    charges = [e for e in sub.get_nowait() if isinstance(e, events.ChargeChanged)]
    assert [e.charging for e in charges] == [False]


def test_local_move_rotates_by_the_angle(runtime: RobotRuntime) -> None:
    sim = runtime.simulation
    start = sim.true_pose.theta
    runtime.local_move(rotate=math.pi / 2)
    runtime.advance(5.0)
    assert abs(angle_diff(sim.true_pose.theta, start + math.pi / 2)) <= 0.05
    assert sim.true_twist.angular == 0.0


def test_local_move_drives_the_distance_backwards(runtime: RobotRuntime) -> None:
    _navigating(runtime)
    sim = runtime.simulation
    start = sim.true_pose
    runtime.local_move(distance=-0.5)
    runtime.advance(5.0)
    moved = sim.true_pose.relative_to(start)
    assert moved.x == pytest.approx(-0.5, abs=0.03)
    assert abs(moved.y) < 0.03
    assert sim.true_twist.linear == 0.0


@pytest.mark.parametrize("navigating", [False, True])
def test_local_move_stops_short_of_a_wall(runtime: RobotRuntime, navigating: bool) -> None:
    if navigating:
        _navigating(runtime)
    sim = runtime.simulation
    runtime.local_move(distance=10.0)
    runtime.advance(30.0)
    assert sim.collisions == []
    assert sim.true_twist.linear == 0.0
    assert sim.true_pose.x - 8.0 > 1.0
    assert sim.true_pose.x - 8.0 < 10.0 - 1.0


def test_local_move_requests_are_validated(runtime: RobotRuntime) -> None:
    with pytest.raises(InvalidRequest):
        runtime.local_move()
    with pytest.raises(InvalidRequest):
        runtime.local_move(rotate=1.0, distance=1.0)
    with pytest.raises(InvalidRequest):
        runtime.local_move(distance=math.inf)


def test_status_snapshot_has_the_contract_keys(runtime: RobotRuntime) -> None:
    runtime.advance(0.2)
    body = runtime.status().to_dict()
    assert set(body) == {"mode", "map", "floor", "floor_level", "pose", "velocity", "battery",
                         "estop", "localization", "navigation", "stamp", "frame", "mapping",
                         "doors"}
    assert body["mode"] == "free" and body["mapping"] is None  # no mapping session
    assert body["stamp"] == pytest.approx(0.2, abs=0.06)


def test_the_snapshot_carries_the_floor_level_and_sees_it_change(
    runtime: RobotRuntime, store: SiteStore
) -> None:
    runtime.advance(0.2)
    status = runtime.status()
    assert status.floor is not None
    assert status.floor_level == store.floor(status.floor).level
    store.save_floor(dataclasses.replace(store.floor(status.floor), level=7))
    runtime.advance(0.2)
    assert runtime.status().floor_level == 7


def test_loop_thread_reaches_a_goal_at_speed_50(world: World, store: SiteStore) -> None:
    runtime = RobotRuntime.simulated(
        store, world, config=RuntimeConfig(speed=50.0, people=False))
    sub = runtime.bus.subscribe()
    done = threading.Event()
    seen: list[str] = []

    def watch() -> None:
        while not done.is_set():
            for event in sub.wait(timeout=1.0):
                seen.append(event.kind)
                if event.kind in ("navigation_succeeded", "navigation_failed"):
                    done.set()

    watcher = threading.Thread(target=watch, daemon=True)
    watcher.start()
    runtime.start()
    try:
        with pytest.raises(Conflict):
            runtime.advance(1.0)
        runtime.start_navigation("floor1")
        attempt_id = runtime.go_to(point="lobby")
        assert done.wait(timeout=120.0)
    finally:
        runtime.stop()
        done.set()
        watcher.join(timeout=10.0)
    assert attempt_id == 1
    assert [k for k in seen if k.startswith("navigation")] == [
        "navigation_started", "navigation_succeeded"]
    assert not runtime.running


def test_a_new_navigation_session_starts_idle(runtime: RobotRuntime) -> None:
    _navigating(runtime)
    runtime.go_to(point="lobby")
    runtime.advance(1.0)
    runtime.start_navigation("floor1")
    status = runtime.status()
    assert (status.navigation_state, status.goal, status.attempt_id) == ("idle", None, None)
    assert runtime.go_to(point="lobby") == 2


def test_a_subscriber_that_never_reads_does_not_hold_the_robot(runtime: RobotRuntime) -> None:
    stuck = runtime.bus.subscribe(maxlen=1)
    _navigating(runtime)
    runtime.go_to(point="lobby")
    assert runtime.advance_until(lambda: _finished(runtime), timeout=120.0)
    assert runtime.status().navigation_state == "succeeded"
    assert stuck.dropped >= 4
    assert [e.kind for e in stuck.get_nowait()] == ["navigation_succeeded"]
