from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from polynav.errors import Conflict
from polynav.runtime import events
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
