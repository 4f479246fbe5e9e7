"""The engine: one running task, pre-emption, detours, giving way, restoring settings."""

from __future__ import annotations

import pytest

from polynav.errors import Conflict, NotFound
from polynav.tasks.control import Sequence
from polynav.tasks.engine import Task, TaskEngine
from polynav.tasks.tree import build
from tests.unit.tasks.scripted import Clockwork, S, Scripted


def _engine() -> tuple[TaskEngine, list[str]]:
    ended: list[str] = []
    engine = TaskEngine(Clockwork())  # type: ignore[arg-type]
    engine.when_ended(lambda t: ended.append(f"{t.name}:{t.state.value}"))
    return engine, ended


def test_starting_a_task_pre_empts_the_running_one() -> None:
    engine, ended = _engine()
    a = engine.add(Task("a", Sequence([Scripted(S.WORKING)])))
    b = engine.add(Task("b", Sequence([Scripted(S.COMPLETE, work=2)])))
    engine.start(a.id)
    engine.start(b.id)
    assert a.state is S.CANCELLED and a.note.startswith("cancelled: another task")
    for _ in range(5):
        engine.tick(0.0)
    assert ended == ["a:CANCELLED", "b:COMPLETE"] and engine.running is None


def test_a_detour_pauses_the_running_task_and_resumes_it_when_it_completes() -> None:
    engine, ended = _engine()
    leaf = Scripted(S.COMPLETE, work=3)
    task = engine.add(Task("round", Sequence([leaf])))
    engine.start(task.id)
    detour = Task("charge", Sequence([Scripted(S.COMPLETE, work=2)]))
    engine.interrupt(detour)
    assert task.state is S.PAUSED and leaf.held == 1 and engine.suspended is task
    with pytest.raises(Conflict):
        engine.interrupt(Task("again", Sequence([Scripted()])))
    for _ in range(10):
        engine.tick(0.0)
    assert ended == ["charge:COMPLETE", "round:COMPLETE"]


def test_a_failed_detour_cancels_the_waiting_task() -> None:
    engine, ended = _engine()
    task = engine.add(Task("round", Sequence([Scripted(S.WORKING)])))
    engine.start(task.id)
    engine.interrupt(Task("charge", Sequence([Scripted(S.FAIL)])))
    assert ended == ["charge:FAIL", "round:CANCELLED"]
    assert "charge ended FAIL" in task.note and engine.running is None


def test_a_command_from_outside_gives_way_but_not_one_from_the_task() -> None:
    engine, ended = _engine()
    task = engine.add(Task("round", Sequence([Scripted(S.WORKING)])))
    engine.start(task.id)
    assert engine.give_way("a goal was sent") is task
    assert task.state is S.CANCELLED and task.note == "a goal was sent"
    assert engine.give_way("again") is None


def test_settings_changed_are_restored_however_the_task_ends() -> None:
    robot = Clockwork()
    robot.settings = {"speed": 1.0}
    engine = TaskEngine(robot)  # type: ignore[arg-type]
    spec = {"name": "slow", "sub_tasks": [
        {"type": "change_setting_action", "settings": {"speed": 0.2},
         "init_settings": {"speed": 1.0}},
        {"type": "wait_req_action"}]}
    task = engine.add(Task("slow", build(spec)))
    engine.start(task.id)
    assert robot.settings["speed"] == 0.2
    engine.cancel(task.id)
    assert robot.settings["speed"] == 1.0


def test_unknown_ids_and_running_tasks() -> None:
    engine, _ = _engine()
    with pytest.raises(NotFound):
        engine.start("nope")
    task = engine.add(Task("w", Sequence([Scripted(S.WORKING)])))
    engine.start(task.id)
    with pytest.raises(Conflict):
        engine.delete(task.id)
    with pytest.raises(NotFound):
        engine.pause(task.id, "no-node")
