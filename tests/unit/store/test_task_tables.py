"""Tasks, schedules and automation tasks in the site store: round trips, cascade, reopen."""

from __future__ import annotations

from pathlib import Path

import pytest

from polynav.errors import InvalidRequest, NotFound
from polynav.store import AutomationRecord, ScheduleRecord, SiteStore, TaskRecord

SPEC = {"name": "go", "sub_tasks": [{"type": "nav_action", "point": "lobby"}],
        "blackboard": {"who": "ada"}}


def _task(task_id: str = "t1", state: str = "WAITTING") -> TaskRecord:
    return TaskRecord(task_id, "go", "native", "task", SPEC, {"who": "ada"}, state, "",
                      "2030-01-07T09:00:00")


def test_a_task_and_its_schedule_round_trip_and_survive_a_reopen(tmp_path: Path) -> None:
    with SiteStore.open(tmp_path / "data") as store:
        store.put_task(_task())
        schedule = ScheduleRecord("s1", "t1", {"mode": "weekly", "weekdays": ["monday"],
                                               "times": ["09:00"], "loop": 0},
                                  True, 2, "2030-01-14T09:00:00", "2030-01-07T09:00:00")
        store.put_schedule(schedule)
        store.set_task_state("t1", "WORKING", "", "2030-01-07T09:00:01")
    with SiteStore.open(tmp_path / "data") as store:
        assert store.tasks() == [TaskRecord("t1", "go", "native", "task", SPEC, {"who": "ada"},
                                            "WORKING", "", "2030-01-07T09:00:01")]
        assert store.schedules() == [schedule]
        assert store.schedules("t1") == [schedule] and store.schedules("t2") == []
        assert store.schedule("s1") == schedule


def test_replacing_a_task_keeps_its_schedules_and_deleting_it_takes_them(
        empty_store: SiteStore) -> None:
    empty_store.put_task(_task())
    empty_store.put_schedule(ScheduleRecord("s1", "t1", {"mode": "once"}))
    empty_store.put_task(_task(state="COMPLETE"))
    assert [s.id for s in empty_store.schedules()] == ["s1"]
    assert empty_store.task("t1").state == "COMPLETE"
    empty_store.delete_task("t1")
    assert empty_store.tasks() == [] and empty_store.schedules() == []
    with pytest.raises(NotFound):
        empty_store.task("t1")


def test_a_schedule_for_a_task_not_stored_is_refused(empty_store: SiteStore) -> None:
    with pytest.raises(NotFound, match="t9"):
        empty_store.put_schedule(ScheduleRecord("s1", "t9", {}))
    assert empty_store.schedules() == []
    with pytest.raises(NotFound):
        empty_store.delete_schedule("s1")


def test_a_spec_that_is_not_json_is_refused(empty_store: SiteStore) -> None:
    with pytest.raises(InvalidRequest, match="task.spec"):
        empty_store.put_task(TaskRecord("t1", "n", "native", "task", {"x": float("nan")}, {},
                                        "WAITTING"))
    assert empty_store.tasks() == []


def test_automation_crud(empty_store: SiteStore) -> None:
    record = AutomationRecord("a1", "Greet", "says hi", "print('hi')", "<xml/>", False, None,
                              1700000000.5)
    assert empty_store.put_automation(record) == record
    changed = AutomationRecord("a1", "Greet", "says hi", "pass", "<xml/>", True, "k3y",
                               1700000000.5)
    empty_store.put_automation(changed)
    assert empty_store.automations() == [changed]
    assert empty_store.automation("a1") == changed
    empty_store.delete_automation("a1")
    assert empty_store.automations() == []
    with pytest.raises(NotFound):
        empty_store.automation("a1")
    with pytest.raises(NotFound):
        empty_store.delete_automation("a1")
