"""Acceptance: a schedule and a task survive ``kill -9`` of ``python -m polynav run``.

Both runs start their calendar at the same fixed epoch (``--calendar-epoch``), so the weekly
start (Monday 09:00) comes 90 simulated seconds after each start-up: not before the kill, and
again after the restart. A task working at the kill comes back CANCELLED, interrupted.
"""

from __future__ import annotations

import signal
import subprocess
import sys
from pathlib import Path

import pytest

from tests.api import test_blackbox
from tests.api.test_blackbox import PolynavProcess, wait_for

EPOCH = "2030-01-07T08:58:30"  # a Monday


@pytest.fixture
def with_epoch(monkeypatch: pytest.MonkeyPatch) -> None:
    real = subprocess.Popen

    def popen(args: list[str], **kwargs: object) -> subprocess.Popen[str]:
        if args[:3] == [sys.executable, "-m", "polynav"]:
            args = [*args, "--calendar-epoch", EPOCH]
        return real(args, **kwargs)  # type: ignore[call-overload, no-any-return]

    monkeypatch.setattr(test_blackbox.subprocess, "Popen", popen)


def test_a_weekly_schedule_and_an_interrupted_task_survive_sigkill(
        tmp_path: Path, with_epoch: None) -> None:
    data = tmp_path / "data"
    first = PolynavProcess(data)
    try:
        http = first.http
        working = http.post("/api/tasks", params={"start": True}, json={
            "name": "long", "sub_tasks": [{"type": "sleep_action", "wait_time": 3000.0}]})
        assert working.status_code == 201, working.text
        task = http.post("/api/tasks", json={
            "name": "nap", "sub_tasks": [{"type": "sleep_action", "wait_time": 1.0}]}).json()
        made = http.post("/api/schedules", json={
            "task_id": task["id"], "mode": "weekly", "weekdays": ["monday"],
            "times": ["09:00"]})
        assert made.status_code == 201, made.text
        assert made.json()["next_fire"] == "2030-01-07T09:00:00"
    finally:
        assert first.close(signal.SIGKILL) == -signal.SIGKILL
    second = PolynavProcess(data)
    try:
        http = second.http
        interrupted = http.get(f"/api/tasks/{working.json()['id']}").json()
        assert (interrupted["state"], interrupted["note"]) == (
            "CANCELLED", "interrupted: the robot restarted")
        assert [s["id"] for s in http.get("/api/schedules").json()] == [made.json()["id"]]
        assert http.get(f"/api/tasks/{task['id']}").json()["state"] == "WAITTING"
        wait_for(lambda: http.get(f"/api/tasks/{task['id']}").json()["state"] != "WAITTING",
                 60.0, "the schedule never started its task after the restart")
        shown = http.get(f"/api/schedules/{made.json()['id']}").json()
        assert (shown["starts"], shown["next_fire"]) == (1, "2030-01-14T09:00:00")
    finally:
        second.close()
