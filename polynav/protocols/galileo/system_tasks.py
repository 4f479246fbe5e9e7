"""Device jobs as Galileo task objects (galileo-http-a §1.8, A-19, A-36).

Slide and jacking moves and video recordings are tasks in Galileo: the endpoint returns a task
object with one action, and the task API controls it. :class:`DeviceTasks` (one per adapter,
``ctx.state``) remembers which task id stands for which device job, and builds the object in
the vendor's words from the job's live state: ``WORKING`` while it runs, ``COMPLETE`` when done,
``CANCELLED`` when stopped or replaced, ``ERROR`` on a fault. :func:`device_task` and
:func:`stop_device_task` are what the task endpoints (``/api/v1/task?id=``, ``/task/stop``) call
for an id they do not know themselves.
"""

from __future__ import annotations

import threading
import uuid
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.messages import TaskState
from polynav.robot.devices import DeviceJob, JobState

_STATE = {
    JobState.WORKING: TaskState.WORKING,
    JobState.COMPLETE: TaskState.COMPLETE,
    JobState.CANCELLED: TaskState.CANCELLED,
    JobState.ERROR: TaskState.ERROR,
}

#: The recording action's type: the document names none (A-36).
VIDEO_ACTION = "record_video_action"


@dataclass(slots=True)
class _Task:
    task_id: str
    action_id: str
    name: str
    action: dict[str, Any]  # type and parameters, without id and progress
    job: Callable[[], DeviceJob | None]
    stop: Callable[[], object]


@dataclass
class DeviceTasks:
    """Task id -> the device job it stands for."""

    tasks: dict[str, _Task] = field(default_factory=dict)
    lock: threading.Lock = field(default_factory=threading.Lock)

    def add(self, name: str, action: dict[str, Any], job: Callable[[], DeviceJob | None],
            stop: Callable[[], object]) -> _Task:
        task = _Task(str(uuid.uuid4()), str(uuid.uuid4()), name, action, job, stop)
        with self.lock:
            self.tasks[task.task_id] = task
            while len(self.tasks) > 512:  # ids are never reused; keep the recent ones
                del self.tasks[next(iter(self.tasks))]
        return task

    def get(self, task_id: str) -> _Task | None:
        with self.lock:
            return self.tasks.get(task_id)


def tasks(ctx: Context) -> DeviceTasks:
    return ctx.state("galileo.system_tasks", DeviceTasks)


def task_object(task: _Task) -> dict[str, Any]:
    """The task in the document's shape (the example at seed lines 2014-2068)."""
    job = task.job()
    state = _STATE[job.state] if job is not None else TaskState.ERROR
    progress = float(job.progress) if job is not None else 0.0
    # The fields of the example (seed lines 2014-2068), plus the ``state`` and ``result`` every
    # action carries in the task model (galileo-tasks-bt-ws §2.4).
    action = {"id": task.action_id, **task.action, "progress": progress,
              "state": state.value, "result": job.reason if job is not None else "lost"}
    return {
        "id": task.task_id,
        "name": task.name,
        "loop_flag": False,
        "current_task": action,
        "state": state.value,
        "sub_tasks": [dict(action)],
        "progress": progress,
        "loop_count": 0,
    }


def device_task(ctx: Context, task_id: str) -> dict[str, Any] | None:
    """The task object of a device task, or ``None`` when ``task_id`` is not one."""
    task = tasks(ctx).get(task_id)
    return task_object(task) if task is not None else None


def stop_device_task(ctx: Context, task_id: str) -> dict[str, Any] | None:
    """Stop a device task (a recording saves its file); its task object after, or ``None``
    when ``task_id`` is not one."""
    task = tasks(ctx).get(task_id)
    if task is None:
        return None
    job = task.job()
    if job is not None and job.state is JobState.WORKING:
        task.stop()
    return task_object(task)
