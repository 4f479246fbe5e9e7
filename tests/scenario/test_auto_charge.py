"""Auto-charge on the simulated demo robot: below the low threshold the running patrol waits,
the robot docks, charges to full, and the patrol goes on and finishes. Simulated time; the
battery drains and charges fast so the whole story takes minutes of simulated time."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import replace
from pathlib import Path

import pytest

from polynav.geometry import Pose2D
from polynav.robot.sim.config import SimConfig
from polynav.runtime import events
from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.tasks.patrol import PatrolPlan
from polynav.worlds.world import World

FAST = SimConfig(battery_start_percent=21.0, battery_drain_per_metre=0.15,
                 battery_charge_rate=7200.0, battery_internal_resistance=0.0)


@pytest.fixture
def runtime(world: World, tmp_path: Path) -> Iterator[RobotRuntime]:
    with SiteStore.open(tmp_path / "data", seed_world=world) as store:
        rt = RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False),
                                    sim_config=FAST)
        rt.start_navigation("floor1")
        rt.advance(0.5)
        yield rt


WATCHED = {"auto_charge_started", "docking_succeeded", "auto_charge_ended", "patrol_started",
           "patrol_finished", "patrol_failed", "patrol_canceled", "low_battery"}


def test_auto_charge_triggers_mid_patrol_charges_and_the_patrol_finishes(
        runtime: RobotRuntime) -> None:
    sub = runtime.bus.subscribe(maxlen=100_000)
    runtime.patrol(PatrolPlan(("lobby", "corridor_west", "front_desk"), count=2))
    assert runtime.advance_until(lambda: runtime.status().patrol_state != "running", 900.0)
    seen = [e for e in sub.get_nowait() if e.kind in WATCHED]
    kinds = [e.kind for e in seen]
    assert runtime.status().patrol_state == "succeeded", kinds
    assert kinds.index("low_battery") < kinds.index("auto_charge_started") \
        < kinds.index("docking_succeeded") < kinds.index("auto_charge_ended") \
        < kinds.index("patrol_finished")
    started = next(e for e in seen if isinstance(e, events.AutoChargeStarted))
    ended = next(e for e in seen if isinstance(e, events.AutoChargeEnded))
    assert started.charger == "charger" and started.percent < 20.0
    assert started.task_id is not None
    assert ended.charged and ended.percent >= 95.0
    assert kinds.count("auto_charge_started") == 1
    assert not runtime.status().charging  # it left the charger to finish the patrol


def test_with_auto_charge_off_the_patrol_runs_on(runtime: RobotRuntime) -> None:
    runtime.update_settings({"auto_charge": 0.0})
    sub = runtime.bus.subscribe(maxlen=100_000)
    runtime.patrol(PatrolPlan(("lobby", "corridor_west"), count=1))
    assert runtime.advance_until(lambda: runtime.status().patrol_state != "running", 300.0)
    kinds = [e.kind for e in sub.get_nowait()]
    assert "low_battery" in kinds and "auto_charge_started" not in kinds
    assert runtime.status().patrol_state == "succeeded"


def test_a_failed_charge_cancels_the_waiting_task(runtime: RobotRuntime) -> None:
    # The charger point moved into the middle of the room: the robot "docks" but no contact
    # ever charges it; the wait for charging fails and the patrol is cancelled, not run flat.
    charger = runtime.store.point("floor1", "charger")
    runtime.store.update_point("floor1", "charger",
                               replace(charger, pose=Pose2D(5.5, 10.0, 3.14159)))
    sub = runtime.bus.subscribe(maxlen=100_000)
    runtime.patrol(PatrolPlan(("lobby", "corridor_west", "front_desk"), count=2))
    assert runtime.advance_until(lambda: runtime.status().patrol_state != "running", 900.0)
    ended = [e for e in sub.get_nowait() if isinstance(e, events.AutoChargeEnded)]
    assert ended and not ended[0].charged and ended[0].reason
    assert runtime.status().patrol_state == "canceled"
