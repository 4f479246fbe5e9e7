"""The state and error tables of docs/puwei.md (:mod:`polynav.protocols.puwei.status`), on
snapshots of a real runtime changed field by field."""

from __future__ import annotations

from dataclasses import replace

from polynav.protocols.puwei.status import State, err_codes, state_of
from polynav.runtime.robot_runtime import RobotRuntime


def test_state_precedence_follows_the_table(runtime: RobotRuntime) -> None:
    snap = replace(runtime.status(), mode="navigating", localization_state="tracking",
                   estop_hardware=False, estop_software=False, charging=False,
                   navigation_state="idle")
    assert state_of(snap, task_running=False, task_paused=False) is State.IDLE
    assert state_of(replace(snap, charging=True), task_running=False,
                    task_paused=False) is State.CHARGING
    assert state_of(replace(snap, charging=True), task_running=True,
                    task_paused=False) is State.RUNNING
    assert state_of(replace(snap, navigation_state="paused"), task_running=True,
                    task_paused=False) is State.PAUSED
    assert state_of(replace(snap, mode="busy"), task_running=True,
                    task_paused=True) is State.LOADING
    assert state_of(replace(snap, mode="mapping"), task_running=False,
                    task_paused=False) is State.MAPPING
    assert state_of(replace(snap, localization_state="lost"), task_running=True,
                    task_paused=False) is State.ERROR
    assert state_of(replace(snap, estop_software=True, mode="mapping"), task_running=False,
                    task_paused=False) is State.ERROR


def test_err_lists_every_condition_that_holds(runtime: RobotRuntime) -> None:
    snap = replace(runtime.status(), mode="navigating", localization_state="lost",
                   estop_hardware=True, estop_software=True, charging=False,
                   battery_percent=12.0, navigation_state="failed", reason="stuck",
                   attempt_id=7)
    assert err_codes(snap, low_battery_percent=20.0) == ["1-1", "1-2", "2-1", "3-1", "4-3"]
    assert err_codes(snap, low_battery_percent=20.0, cleared_attempt=7) == [
        "1-1", "1-2", "2-1", "3-1"]
    assert err_codes(replace(snap, reason="something new"), low_battery_percent=10.0) == [
        "1-1", "1-2", "2-1", "4-99"]
    calm = replace(snap, estop_hardware=False, estop_software=False, charging=True,
                   localization_state="uninitialized", navigation_state="succeeded")
    assert err_codes(calm, low_battery_percent=20.0) == ["2-2"]
