from __future__ import annotations

import math

import pytest

from polynav.errors import InvalidRequest
from polynav.robot.devices import AxisMode, JobState
from polynav.robot.sim.devices.axis import AxisConfig, SimAxis

SLIDE = AxisConfig("slide", travel=0.6, default_speed=0.05, homing_speed=0.03, max_speed=0.2,
                   start_position=0.15)
TURNTABLE = AxisConfig("turn", travel=None, default_speed=0.5, homing_speed=0.25,
                       max_speed=1.5, start_position=0.5)


def test_an_unhomed_slide_homes_first_then_runs_to_the_ratio_at_its_default_speed() -> None:
    axis = SimAxis(SLIDE)
    before = axis.state(0.0)
    assert (before.homed, before.position, before.ratio) == (False, 0.0, 0.0)
    job = axis.move(0.0, AxisMode.RATIO, target=0.5)
    # 0.15 m home at 0.03 m/s = 5 s, then 0.3 m at 0.05 m/s = 6 s.
    mid = axis.state(5.0)
    assert mid.homed and mid.position == pytest.approx(0.0, abs=1e-9) and mid.moving
    assert axis.job(5.0, job.job_id).progress == pytest.approx(0.15 / 0.45)
    assert axis.state(8.0).position == pytest.approx(0.15)
    done = axis.state(11.0)
    assert done.position == pytest.approx(0.3) and done.ratio == pytest.approx(0.5)
    assert not done.moving
    finished = axis.job(11.0, job.job_id)
    assert finished is not None and finished.state is JobState.COMPLETE
    assert finished.progress == 1.0


def test_a_homed_slide_moves_directly_and_motion_does_not_depend_on_how_often_it_is_read() -> None:
    a, b = SimAxis(SLIDE), SimAxis(SLIDE)
    for axis in (a, b):
        axis.move(0.0, AxisMode.HOME)
    for t in range(1, 60):
        a.state(t * 0.1)
    b.state(6.0)
    assert a.state(6.0) == b.state(6.0)
    job = a.move(6.0, AxisMode.POSITION, target=0.4, speed=0.1)
    assert a.state(8.0).position == pytest.approx(0.2)
    assert a.job(10.0, job.job_id).state is JobState.COMPLETE
    assert a.state(10.0).position == pytest.approx(0.4)


def test_a_new_move_cancels_the_running_one_and_stop_cancels_too() -> None:
    axis = SimAxis(SLIDE)
    first = axis.move(0.0, AxisMode.HOME)
    second = axis.move(1.0, AxisMode.RATIO, target=1.0, speed=0.2)
    assert axis.job(1.0, first.job_id).state is JobState.CANCELLED
    axis.stop(2.0)
    stopped = axis.job(2.0, second.job_id)
    assert stopped.state is JobState.CANCELLED and 0.0 < stopped.progress < 1.0
    assert not axis.state(3.0).moving


def test_jog_runs_for_its_time_and_stops_at_the_end_of_travel() -> None:
    axis = SimAxis(SLIDE)
    axis.move(0.0, AxisMode.HOME)
    axis.move(10.0, AxisMode.JOG, speed=0.1, duration=2.0)
    assert axis.state(13.0).position == pytest.approx(0.2)
    axis.move(13.0, AxisMode.JOG, speed=-0.1, duration=5.0)
    assert axis.state(20.0).position == pytest.approx(0.0)


def test_bad_moves_are_refused_and_change_nothing() -> None:
    axis = SimAxis(SLIDE)
    axis.move(0.0, AxisMode.HOME)
    axis.state(10.0)
    for kwargs, field in (
        ({"mode": AxisMode.RATIO, "target": 1.5}, "pose"),
        ({"mode": AxisMode.POSITION, "target": 0.9}, "pose"),
        ({"mode": AxisMode.POSITION, "target": math.nan}, "target"),
        ({"mode": AxisMode.POSITION, "target": 0.1, "speed": -1.0}, "speed"),
        ({"mode": AxisMode.JOG, "speed": 0.1}, "time"),
    ):
        with pytest.raises(InvalidRequest) as err:
            axis.move(10.0, **kwargs)  # type: ignore[arg-type]
        assert err.value.field == field
    assert axis.state(20.0).position == pytest.approx(0.0)


def test_the_turntable_takes_the_short_way_and_wraps_the_angle() -> None:
    axis = SimAxis(TURNTABLE)
    axis.move(0.0, AxisMode.POSITION, target=3.0)  # home from 0.5 rad (2 s), then 3 rad (6 s)
    assert axis.state(2.0).homed
    assert axis.state(8.0).position == pytest.approx(3.0)
    axis.move(8.0, AxisMode.POSITION, target=-3.0, speed=1.0)  # 0.28 rad through pi
    state = axis.state(8.0 + (2 * math.pi - 6.0) + 0.01)
    assert state.position == pytest.approx(-3.0)
    with pytest.raises(InvalidRequest):
        axis.move(9.0, AxisMode.RATIO, target=0.5)


def test_a_fault_stops_the_axis_with_an_error_and_it_must_home_again() -> None:
    axis = SimAxis(SLIDE)
    job = axis.move(0.0, AxisMode.RATIO, target=0.5)
    axis.set_fault(7.0, "motor overcurrent")
    failed = axis.job(7.0, job.job_id)
    assert failed.state is JobState.ERROR and failed.reason == "motor overcurrent"
    state = axis.state(8.0)
    assert state.fault and not state.homed
