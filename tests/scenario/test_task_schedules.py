"""Schedules and stored tasks on the simulated demo robot, on its simulated calendar.

The calendar starts at a fixed epoch (Monday 7 January 2030, 08:59) so that a schedule fires at
a known simulated second. A restart is a second runtime on the same site store, its calendar
later; a SIGKILL of the real process is in tests/api/test_task_restart.py.
"""

from __future__ import annotations

import datetime as dt
import logging

import pytest

from polynav.errors import Conflict, InvalidRequest, NotFound
from polynav.runtime import events
from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.runtime.task_commands import INTERRUPTED
from polynav.store.site_store import SiteStore
from polynav.tasks import schedule as schedule_module
from polynav.worlds.world import World

EPOCH = dt.datetime(2030, 1, 7, 8, 59)  # a Monday
SLEEP = {"name": "nap", "sub_tasks": [{"type": "sleep_action", "wait_time": 5.0}]}
WEEKLY_9 = {"mode": "weekly", "weekdays": ["monday"], "times": ["09:00"]}


def _runtime(store: SiteStore, world: World, epoch: dt.datetime = EPOCH) -> RobotRuntime:
    return RobotRuntime.simulated(store, world, config=RuntimeConfig(
        people=False, calendar_epoch=epoch))


def _fired(sub: object) -> list[events.RuntimeEvent]:
    return [e for e in sub.get_nowait()  # type: ignore[attr-defined]
            if isinstance(e, events.ScheduleFired | events.ScheduleSkipped)]


def test_a_weekly_schedule_starts_its_task_at_its_simulated_time(
        store: SiteStore, world: World) -> None:
    rt = _runtime(store, world)
    task = rt.tasks.create(SLEEP)
    made = rt.tasks.schedules.create(task["id"], WEEKLY_9)
    assert made["next_fire"] == "2030-01-07T09:00:00"
    sub = rt.bus.subscribe()
    rt.advance(59.5)
    assert rt.tasks.get(task["id"])["state"] == "WAITTING" and _fired(sub) == []
    rt.advance(1.0)
    assert rt.tasks.get(task["id"])["state"] == "WORKING"
    fired = _fired(sub)
    assert [(type(e), e.due) for e in fired] == [  # type: ignore[attr-defined]
        (events.ScheduleFired, "2030-01-07T09:00:00")]
    shown = rt.tasks.schedules.get(made["id"])
    assert (shown["starts"], shown["next_fire"]) == (1, "2030-01-14T09:00:00")
    assert shown["last"]["outcome"] == "started"
    assert store.schedule(made["id"]).next_fire == "2030-01-14T09:00:00"


def test_bad_schedules_change_nothing(store: SiteStore, world: World) -> None:
    rt = _runtime(store, world)
    task = rt.tasks.create(SLEEP)
    temporary = rt.tasks.create(SLEEP, temporary=True)
    for spec, error in [({"mode": "once", "at": "2030-01-07T08:58:00"}, InvalidRequest),
                        ({"mode": "once", "at": "2030-02-30T09:00:00"}, InvalidRequest),
                        ({"mode": "monthly", "days": [32], "times": ["09:00"]}, InvalidRequest),
                        ({"mode": "weekly", "weekdays": ["caturday"], "times": ["09:00"]},
                         InvalidRequest),
                        ({"mode": "weekly", "weekdays": ["mon"], "times": ["25:00"]},
                         InvalidRequest)]:
        with pytest.raises(error):
            rt.tasks.schedules.create(task["id"], spec)
    with pytest.raises(NotFound):
        rt.tasks.schedules.create("no-such-task", WEEKLY_9)
    with pytest.raises(Conflict, match="not kept"):
        rt.tasks.schedules.create(temporary["id"], WEEKLY_9)
    assert rt.tasks.schedules.list() == [] and store.schedules() == []


def test_a_restart_keeps_tasks_and_schedules_and_cancels_the_interrupted_task(
        store: SiteStore, world: World) -> None:
    rt = _runtime(store, world)
    running = rt.tasks.create(SLEEP | {"name": "running"}, start=True)
    waiting = rt.tasks.create(SLEEP | {"name": "waiting"})
    missed = rt.tasks.schedules.create(waiting["id"], WEEKLY_9)
    kept = rt.tasks.schedules.create(waiting["id"], {"mode": "weekly", "weekdays": ["tue"],
                                                     "times": ["09:00"]})
    rt.advance(1.0)
    assert store.task(running["id"]).state == "WORKING"
    # "Restart" at 09:30: the Monday 09:00 start came due while off.
    again = _runtime(store, world, EPOCH + dt.timedelta(minutes=31))
    sub = again.bus.subscribe()
    assert again.tasks.get(running["id"])["state"] == "CANCELLED"
    assert again.tasks.get(running["id"])["note"] == INTERRUPTED
    assert store.task(running["id"]).state == "CANCELLED"
    assert again.tasks.get(waiting["id"])["state"] == "WAITTING"
    again.advance(0.2)
    skipped = _fired(sub)
    assert [(type(e), e.schedule_id, e.due) for e in skipped] == [  # type: ignore[attr-defined]
        (events.ScheduleSkipped, missed["id"], "2030-01-07T09:00:00")]
    assert again.tasks.get(waiting["id"])["state"] == "WAITTING"  # not run late
    shown = {s["id"]: s for s in again.tasks.schedules.list()}
    assert shown[missed["id"]]["next_fire"] == "2030-01-14T09:00:00"
    assert shown[kept["id"]]["next_fire"] == "2030-01-08T09:00:00"
    again.tasks.delete(waiting["id"])
    assert again.tasks.schedules.list() == [] and store.schedules() == []


def test_a_due_start_waits_for_another_task_then_is_skipped_at_the_limit(
        store: SiteStore, world: World, monkeypatch: pytest.MonkeyPatch,
        caplog: pytest.LogCaptureFixture) -> None:
    monkeypatch.setattr("polynav.runtime.task_schedules.BUSY_WAIT", 20.0)
    rt = _runtime(store, world)
    long = rt.tasks.create({"name": "long", "sub_tasks": [
        {"type": "sleep_action", "wait_time": 200.0}]}, start=True)
    task = rt.tasks.create(SLEEP)
    rt.tasks.schedules.create(task["id"], WEEKLY_9)
    sub = rt.bus.subscribe()
    with caplog.at_level(logging.ERROR):
        rt.advance(70.0)
        assert rt.tasks.get(task["id"])["state"] == "WAITTING"
        assert rt.tasks.get(long["id"])["state"] == "WORKING"  # never pre-empted
        rt.advance(15.0)
    skipped = _fired(sub)
    assert len(skipped) == 1 and isinstance(skipped[0], events.ScheduleSkipped)
    assert "long" in skipped[0].reason and "20 s" in skipped[0].reason
    assert rt.tasks.get(task["id"])["state"] == "WAITTING"
    assert not [r for r in caplog.records if r.levelno >= logging.ERROR]
    assert schedule_module.BUSY_WAIT == 300.0


def test_a_due_start_waits_while_mapping_and_starts_when_it_ends(
        store: SiteStore, world: World) -> None:
    rt = _runtime(store, world)
    task = rt.tasks.create(SLEEP)
    rt.tasks.schedules.create(task["id"], WEEKLY_9)
    rt.start_mapping()
    rt.advance(65.0)
    assert rt.tasks.get(task["id"])["state"] == "WAITTING"
    assert rt.tasks.schedules.list()[0]["waiting"] == "2030-01-07T09:00:00"
    rt.cancel_mapping()
    rt.advance(0.2)
    assert rt.tasks.get(task["id"])["state"] == "WORKING"


def test_a_due_start_waits_for_docking_to_finish(store: SiteStore, world: World) -> None:
    rt = _runtime(store, world, EPOCH - dt.timedelta(minutes=10))
    rt.start_navigation("floor1")
    rt.advance(0.5)
    rt.go_to(point="charger")
    assert rt.advance_until(lambda: rt.status().phase == "dock", 400.0)
    task = rt.tasks.create(SLEEP)
    at = (rt.calendar_now() + dt.timedelta(seconds=2)).replace(microsecond=0)
    rt.tasks.schedules.create(task["id"], {"mode": "once", "at": at.isoformat()})
    rt.advance(2.5)
    assert rt.status().phase == "dock", "docking ended before the start came due"
    assert rt.tasks.get(task["id"])["state"] == "WAITTING"
    assert rt.advance_until(lambda: rt.tasks.get(task["id"])["state"] != "WAITTING", 120.0)
    assert rt.status().navigation_state == "succeeded"  # the docking was not cut
    assert rt.status().charging
