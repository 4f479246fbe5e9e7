"""Docking by what the robot sees, on the simulated demo robot (simulated time).

The site's charger point (the marker) is 10 cm and 5 degrees off the simulated charger: docking
onto the plate the lidar sees still puts the contacts on the charger's, while docking onto the
marker's pose (``dock_by_sight`` off, the way it was done before) stops off the contacts. A
marker where no charger stands, or a dock asked at a pose where there is none, fails with a
message that says so, the robot standing at the approach.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import replace
from pathlib import Path

import pytest

from polynav.geometry import Pose2D, angle_diff
from polynav.nav.attempt import GoalOptions
from polynav.nav.navigator_config import NavigatorConfig
from polynav.nav.stack import StackConfig
from polynav.runtime import events
from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds.world import World

CHARGER = Pose2D(0.8, 14.0, math.pi)  # the demo's charger: where a docked robot stands
MARKER = CHARGER.compose(Pose2D(-0.06, 0.08, math.radians(5.0)))  # 10 cm, 5 degrees off


def _runtime(world: World, tmp_path: Path, *, by_sight: bool) -> Iterator[RobotRuntime]:
    stack = StackConfig(navigator=NavigatorConfig(dock_by_sight=by_sight))
    with SiteStore.open(tmp_path / "data", seed_world=world) as store:
        rt = RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False),
                                    stack_config=stack)
        charger = store.point("floor1", "charger")
        store.update_point("floor1", "charger", replace(charger, pose=MARKER))
        rt.start_navigation("floor1")
        rt.advance(0.5)
        yield rt


@pytest.fixture
def runtime(world: World, tmp_path: Path) -> Iterator[RobotRuntime]:
    yield from _runtime(world, tmp_path, by_sight=True)


@pytest.fixture
def by_marker(world: World, tmp_path: Path) -> Iterator[RobotRuntime]:
    yield from _runtime(world, tmp_path, by_sight=False)


def _message(rt: RobotRuntime) -> str:
    stack = rt.navigation_stack
    assert stack is not None and stack.navigator.attempt is not None
    return stack.navigator.attempt.message


def _dock(rt: RobotRuntime, **goal: object) -> list[events.RuntimeEvent]:
    sub = rt.bus.subscribe(maxlen=100_000)
    rt.go_to(**goal)  # type: ignore[arg-type]
    assert rt.advance_until(lambda: rt.status().navigation_state not in ("running", "paused"),
                            240.0)
    rt.advance(1.0)
    return [e for e in sub.get_nowait() if e.kind.startswith("docking")]


def test_a_marker_10_cm_and_5_degrees_off_still_docks_by_sight(runtime: RobotRuntime) -> None:
    seen = _dock(runtime, point="charger")
    assert [e.kind for e in seen] == ["docking_started", "docking_succeeded"]
    assert runtime.status().navigation_state == "succeeded" and runtime.status().charging
    truth = runtime.simulation.true_pose
    assert truth.distance_to(CHARGER) < 0.02
    assert abs(angle_diff(truth.theta, CHARGER.theta)) < math.radians(1.5)
    assert runtime.simulation.collisions == []


def test_docking_onto_the_marker_alone_misses_the_contacts(by_marker: RobotRuntime) -> None:
    seen = _dock(by_marker, point="charger")
    assert [e.kind for e in seen] == ["docking_started", "docking_failed"]
    failed = seen[-1]
    assert isinstance(failed, events.DockingFailed) and failed.cause == "no_contact"
    assert not by_marker.status().charging
    assert by_marker.simulation.true_pose.distance_to(CHARGER) > 0.05


def test_a_charger_marker_where_no_charger_stands_fails_no_feature(
        runtime: RobotRuntime) -> None:
    charger = runtime.store.point("floor1", "charger")
    runtime.store.update_point("floor1", "charger",
                               replace(charger, pose=Pose2D(5.5, 10.0, math.pi)))
    seen = _dock(runtime, point="charger")
    assert [e.kind for e in seen] == ["docking_started", "docking_failed"]
    assert isinstance(seen[-1], events.DockingFailed) and seen[-1].cause == "no_feature"
    status = runtime.status()
    assert status.navigation_state == "failed" and not status.charging
    assert "no charger's plate" in _message(runtime)


def test_a_dock_asked_at_a_pose_with_nothing_to_dock_to_says_so(runtime: RobotRuntime) -> None:
    start = runtime.simulation.true_pose
    seen = _dock(runtime, pose=Pose2D(8.0, 8.5, 0.0), options=GoalOptions(dock=True))
    assert [e.kind for e in seen] == ["docking_started", "docking_failed"]
    status = runtime.status()
    assert status.navigation_state == "failed"
    assert "no charger's plate" in _message(runtime)
    # It stood at the approach and looked: it did not drive on into whatever is there.
    end = runtime.simulation.true_pose
    assert end.distance_to(Pose2D(7.5, 8.5, 0.0)) < 0.15, (start, end)
