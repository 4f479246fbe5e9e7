from __future__ import annotations

import datetime as dt
import logging
from collections.abc import Iterator
from pathlib import Path

import pytest

from polynav.errors import Conflict
from polynav.runtime import events
from polynav.runtime.busy import in_lift_car
from polynav.runtime.robot_runtime import Mode, RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds import load_world


@pytest.fixture
def runtime(tmp_path: Path) -> Iterator[RobotRuntime]:
    world = load_world("demo")
    with SiteStore.open(tmp_path / "data", seed_world=world) as store:
        yield RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False))


def test_a_free_robot_reboots_free_and_refuses_commands_while_off(runtime: RobotRuntime) -> None:
    sub = runtime.bus.subscribe()
    runtime.device.power.shutdown(reboot=True, delay=30.0)
    runtime.advance(10.1)
    assert not runtime.powered
    with pytest.raises(Conflict, match="powered off"):
        runtime.start_navigation("floor1")
    runtime.advance(34.0)  # 5 s + the 30 s delay, less a second
    assert not runtime.powered
    runtime.advance(1.0)
    assert runtime.powered and runtime.mode is Mode.FREE
    notices = [e for e in sub.get_nowait() if isinstance(e, events.PowerOffNotice)]
    assert [(n.reboot, n.after, n.delay) for n in notices] == [(True, 10.0, 30.0)]


def test_a_navigating_robot_comes_back_navigating_on_its_map(runtime: RobotRuntime) -> None:
    runtime.start_navigation("floor2")
    runtime.advance(0.5)
    runtime.set_software_estop(True)
    runtime.device.power.shutdown(reboot=True)
    with pytest.raises(Conflict, match="under way"):
        runtime.device.power.shutdown(reboot=False)
    with pytest.raises(Conflict, match="under way"):
        runtime.device.power.restart_software()
    runtime.advance(15.5)
    assert runtime.powered and runtime.map_name == "floor2"
    assert not runtime.status().estop_software
    assert not runtime.device.power.shutting_down


def test_a_service_restart_reloads_navigation_at_once(runtime: RobotRuntime) -> None:
    runtime.start_navigation("floor1")
    runtime.advance(0.5)
    sub = runtime.bus.subscribe()
    runtime.device.power.restart_software()
    kinds = [e.kind for e in sub.get_nowait()]
    assert kinds[0] == "software_shutdown_notice"
    assert runtime.mode is Mode.NAVIGATING and runtime.map_name == "floor1"


def test_timers_run_in_order_on_simulated_time_and_a_failing_one_is_contained(
    runtime: RobotRuntime,
) -> None:
    ran: list[str] = []

    def fail() -> None:
        ran.append("fail")
        raise Conflict("cannot")

    runtime.run_between_ticks(lambda: runtime.schedule(2.0, lambda: ran.append("late")))
    runtime.run_between_ticks(lambda: runtime.schedule(1.0, fail))
    runtime.advance(1.5)
    assert ran == ["fail"]
    runtime.advance(1.0)
    assert ran == ["fail", "late"]


# -- timers never fail half-done (issue 32) ------------------------------------------------------


def _errors(caplog: pytest.LogCaptureFixture) -> list[logging.LogRecord]:
    return [r for r in caplog.records if r.levelno >= logging.ERROR]


def test_a_power_off_asked_while_mapping_is_refused_and_nothing_changes(
        runtime: RobotRuntime) -> None:
    runtime.start_mapping()
    with pytest.raises(Conflict, match="stop .* or cancel mapping"):
        runtime.device.power.shutdown(reboot=False)
    assert not runtime.device.power.shutting_down
    runtime.advance(11.0)
    assert runtime.powered and runtime.mode is Mode.MAPPING


def test_mapping_started_during_the_notice_is_refused_and_the_cut_completes(
        runtime: RobotRuntime, caplog: pytest.LogCaptureFixture) -> None:
    runtime.device.power.shutdown(reboot=True)
    with pytest.raises(Conflict, match="shutdown is under way"):
        runtime.start_mapping()
    with caplog.at_level(logging.ERROR):
        runtime.advance(10.1)
        assert not runtime.powered and runtime.mode is Mode.FREE
        runtime.advance(5.5)
    assert runtime.powered and not runtime.device.power.shutting_down
    assert _errors(caplog) == []
    runtime.start_mapping()  # allowed again once back on
    assert runtime.mode is Mode.MAPPING


def test_a_power_off_during_docking_ends_the_docking_first(
        runtime: RobotRuntime, caplog: pytest.LogCaptureFixture) -> None:
    runtime.start_navigation("floor1")
    runtime.advance(0.5)
    task = runtime.tasks.create({"name": "dock", "sub_tasks": [
        {"type": "nav_action", "point": "charger"}]}, start=True)
    assert runtime.advance_until(lambda: runtime.status().phase == "dock", 400.0)
    runtime.device.power.notice_lead = 0.2  # the cut lands inside the docking
    with caplog.at_level(logging.ERROR):
        runtime.device.power.shutdown(reboot=False)
        runtime.advance(0.3)
    assert not runtime.powered and runtime.mode is Mode.FREE
    assert runtime.status().navigation_state in ("canceled", "idle")
    shown = runtime.tasks.get(task["id"])
    assert (shown["state"], shown["note"]) == ("CANCELLED", "cancelled: the robot powered off")
    assert _errors(caplog) == []


def test_a_power_off_asked_in_a_lift_car_is_refused_and_the_ride_goes_on(
        runtime: RobotRuntime, caplog: pytest.LogCaptureFixture) -> None:
    runtime.start_navigation("floor1")
    runtime.advance(0.5)
    runtime.go_to(point="room_301", map_name="floor3")
    assert runtime.advance_until(lambda: in_lift_car(runtime) is not None, 400.0)
    with pytest.raises(Conflict, match="riding lift lift_1"):
        runtime.device.power.shutdown(reboot=False)
    assert not runtime.device.power.shutting_down
    task = runtime.tasks.create({"name": "later", "sub_tasks": [
        {"type": "sleep_action", "wait_time": 1.0}]})
    at = (runtime.calendar_now() + dt.timedelta(seconds=2)).replace(microsecond=0)
    runtime.tasks.schedules.create(task["id"], {"mode": "once", "at": at.isoformat()})
    runtime.advance(3.0)
    assert runtime.tasks.get(task["id"])["state"] == "WAITTING"  # waits: riding a lift
    assert runtime.tasks.schedules.list()[0]["waiting"] == at.isoformat()
    with caplog.at_level(logging.ERROR):
        assert runtime.advance_until(
            lambda: runtime.tasks.get(task["id"])["state"] != "WAITTING", 400.0)
    assert runtime.status().navigation_state == "succeeded"  # the ride was not cut
    assert runtime.map_name == "floor3"
    assert _errors(caplog) == []


def test_a_cut_that_finds_the_robot_in_a_lift_car_waits_until_it_is_out(
        runtime: RobotRuntime, caplog: pytest.LogCaptureFixture) -> None:
    runtime.start_navigation("floor1")
    runtime.advance(0.5)
    runtime.go_to(point="room_301", map_name="floor3")
    # A shutdown announced just before the robot entered the car: its cut comes inside.
    assert runtime.advance_until(lambda: in_lift_car(runtime) is not None, 400.0)
    power = runtime.device.power
    power._pending = True
    runtime.run_between_ticks(lambda: runtime.schedule(0.0, lambda: power._power_off(
        False, 0.0, power.notice_lead)))
    with caplog.at_level(logging.ERROR):
        runtime.advance(1.0)
        assert runtime.powered and in_lift_car(runtime) is not None  # the cut waits
        assert runtime.advance_until(lambda: not runtime.powered, 400.0)
    assert in_lift_car(runtime) is None and runtime.simulation.floor == "floor3"
    assert _errors(caplog) == []
