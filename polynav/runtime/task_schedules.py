"""Schedules that start stored tasks on the robot's calendar, and the loop that runs them.

A schedule (:mod:`polynav.tasks.schedule` for the modes and their arithmetic) starts one stored
task. The runtime's calendar is ``calendar_epoch`` + its clock (docs/decisions.md, "Task
schedules"), so a simulated run fires at its simulated time. Each schedule remembers its next
due start (``next_fire``) in the site store; every control tick the due ones are taken:

* the robot is free: the task starts (``schedule_fired``) and counts toward ``loop``;
* the robot is busy (:func:`~polynav.runtime.busy.busy_reason`: mapping, docking, riding a
  lift, another task or goal): the start waits for it to be free, checked every tick, up to
  :data:`~polynav.tasks.schedule.BUSY_WAIT`, then is skipped (``schedule_skipped``). A
  scheduled start never pre-empts what somebody started, and never fails inside the loop:
  a refusal becomes a skip with its reason;
* it came due while the robot was off (found when the runtime starts): skipped with that
  reason, never run late.

Only the latest due start of a schedule is taken: starts the calendar jumped over (a loop
that fell far behind) are not made up. Commands (create, update, delete) run between ticks.
"""

from __future__ import annotations

import datetime as dt
import logging
import uuid
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from polynav.errors import Conflict, NotFound, PolynavError, StorageError, look_up
from polynav.runtime import events
from polynav.runtime.busy import busy_reason
from polynav.store.records import ScheduleRecord
from polynav.tasks.engine import TaskEngine
from polynav.tasks.schedule import BUSY_WAIT, ScheduleSpec, check_not_past

if TYPE_CHECKING:
    from polynav.runtime.robot_runtime import RobotRuntime

log = logging.getLogger(__name__)

OFF = "the robot was off when it came due"


@dataclass
class _Schedule:
    id: str
    task_id: str
    spec: ScheduleSpec
    enabled: bool
    starts: int = 0
    next_fire: dt.datetime | None = None
    #: The due start waiting for a busy robot, and since when [s, runtime clock].
    due: dt.datetime | None = None
    waiting_since: float = 0.0
    #: The last due start's outcome: ``{"due", "outcome": started|skipped, "reason"}``.
    last: dict[str, Any] | None = None
    updated: str = ""
    busy_logged: str = field(default="", repr=False)

    def describe(self) -> dict[str, Any]:
        return {"id": self.id, "task_id": self.task_id, **self.spec.to_json(),
                "enabled": self.enabled, "starts": self.starts,
                "next_fire": _iso(self.next_fire), "waiting": _iso(self.due),
                "last": self.last, "updated": self.updated}

    def record(self) -> ScheduleRecord:
        return ScheduleRecord(self.id, self.task_id, self.spec.to_json(), self.enabled,
                              self.starts, _iso(self.next_fire), self.updated)


def _iso(when: dt.datetime | None) -> str | None:
    return None if when is None else when.isoformat(timespec="seconds")


class TaskSchedules:
    """One robot's schedules (``runtime.tasks.schedules``)."""

    def __init__(self, runtime: RobotRuntime, engine: TaskEngine) -> None:
        self._runtime = runtime
        self._engine = engine
        self._schedules: dict[str, _Schedule] = {}
        self._pending: list[events.RuntimeEvent] = []

    # -- reading -------------------------------------------------------------------------------

    def list(self, task_id: str | None = None) -> list[dict[str, Any]]:
        """Every schedule (of one task), in the order they were made."""
        return self._runtime.run_between_ticks(lambda: [
            s.describe() for s in list(self._schedules.values())
            if task_id is None or s.task_id == task_id])

    def get(self, schedule_id: str) -> dict[str, Any]:
        """Raises NotFound."""
        return self._runtime.run_between_ticks(lambda: self._find(schedule_id).describe())

    # -- commands ------------------------------------------------------------------------------

    def create(self, task_id: str, spec: Mapping[str, Any], *, enabled: bool = True
               ) -> dict[str, Any]:
        """Schedule stored task ``task_id`` (``spec``: :meth:`ScheduleSpec.from_json`).

        Raises:
            InvalidRequest: a bad spec, or a once schedule in the past.
            NotFound: no such task. Conflict: the task is not stored (a temporary one).
            StorageError: the store failed. Nothing is made on any error.
        """
        parsed = ScheduleSpec.from_json(spec)

        def run() -> dict[str, Any]:
            self._require_stored_task(task_id)
            first = check_not_past(parsed, self._runtime.calendar_now())
            item = _Schedule(str(uuid.uuid4()), task_id, parsed, enabled, next_fire=first,
                             updated=self._runtime.calendar_iso())
            self._runtime.store.put_schedule(item.record())
            self._schedules[item.id] = item
            log.info("schedule %s for task %s: %s, next %s", item.id, task_id,
                     parsed.to_json(), _iso(first))
            return item.describe()

        return self._runtime.run_between_ticks(run)

    def update(self, schedule_id: str, spec: Mapping[str, Any] | None = None, *,
               enabled: bool | None = None) -> dict[str, Any]:
        """Change when a schedule fires (its count of starts begins again) or switch it on
        or off. Raises as :meth:`create`, and NotFound for no such schedule."""
        parsed = None if spec is None else ScheduleSpec.from_json(spec)

        def run() -> dict[str, Any]:
            item = self._find(schedule_id)
            now = self._runtime.calendar_now()
            new = _Schedule(item.id, item.task_id, parsed or item.spec,
                            item.enabled if enabled is None else enabled,
                            0 if parsed is not None else item.starts,
                            item.next_fire, last=item.last,
                            updated=self._runtime.calendar_iso())
            if parsed is not None:
                new.next_fire = check_not_past(parsed, now)
            elif new.enabled and not item.enabled and item.next_fire is not None \
                    and item.next_fire <= now:
                new.next_fire = new.spec.next_fire(now)  # switched back on: no late start
            self._runtime.store.put_schedule(new.record())
            self._schedules[item.id] = new
            return new.describe()

        return self._runtime.run_between_ticks(run)

    def delete(self, schedule_id: str) -> None:
        """Raises NotFound: no such schedule."""

        def run() -> None:
            self._find(schedule_id)
            self._runtime.store.delete_schedule(schedule_id)
            del self._schedules[schedule_id]

        self._runtime.run_between_ticks(run)

    def forget_task(self, task_id: str) -> None:
        """Drop the schedules of a deleted task (the store dropped its rows with it)."""
        for key in [k for k, s in self._schedules.items() if s.task_id == task_id]:
            del self._schedules[key]

    # -- start-up and the loop -------------------------------------------------------------------

    def load(self) -> None:
        """Bring back the stored schedules; a start that came due while the robot was off is
        skipped (reported on the first tick, when adapters listen), never run late."""
        now = self._runtime.calendar_now()
        for record in self._runtime.store.schedules():
            try:
                spec = ScheduleSpec.from_json(record.spec)
                next_fire = None if record.next_fire is None else dt.datetime.fromisoformat(
                    record.next_fire)
            except (PolynavError, ValueError) as exc:
                log.error("stored schedule %s not loaded: %s", record.id, exc)
                continue
            item = _Schedule(record.id, record.task_id, spec, record.enabled, record.starts,
                             next_fire, updated=record.updated)
            self._schedules[item.id] = item
            if item.enabled and next_fire is not None and next_fire <= now:
                self._skip(item, next_fire, OFF)
                item.next_fire = spec.next_fire(now)
                self._save(item)

    def tick(self, now: float) -> None:
        """Take the due starts (the module docstring). Never raises."""
        if self._pending:
            for event in self._pending:
                self._runtime.publish(event)
            self._pending.clear()
        if not self._schedules:
            return
        calendar_now = self._runtime.calendar_now()
        for item in list(self._schedules.values()):
            if not item.enabled:
                continue
            if item.next_fire is not None and item.next_fire <= calendar_now:
                if item.due is not None:  # still waiting for the one before: that one is lost
                    self._skip(item, item.due, "the robot stayed busy until the next start")
                item.due, item.waiting_since = item.next_fire, now
                item.next_fire = item.spec.next_fire(calendar_now)
                self._save(item)
            if item.due is not None:
                self._try_start(item, now)

    def _try_start(self, item: _Schedule, now: float) -> None:
        due = item.due
        assert due is not None
        reason = busy_reason(self._runtime)
        if reason is not None:
            if now - item.waiting_since >= BUSY_WAIT:
                self._skip(item, due, f"{reason} for {BUSY_WAIT:g} s")
            elif item.busy_logged != reason:
                item.busy_logged = reason
                log.info("schedule %s: due at %s, waiting: %s", item.id, _iso(due), reason)
            return
        try:
            self._engine.start(item.task_id)
        except PolynavError as exc:  # the task went, or will not start: a skip, not a crash
            self._skip(item, due, str(exc))
            return
        item.due, item.busy_logged = None, ""
        item.starts += 1
        item.last = {"due": _iso(due), "outcome": "started", "reason": ""}
        if item.spec.loop and item.starts >= item.spec.loop:
            item.next_fire = None
        log.info("schedule %s started task %s (start %d)", item.id, item.task_id, item.starts)
        self._runtime.publish(events.ScheduleFired(
            self._runtime.now(), item.id, item.task_id, _iso(due) or "", item.starts))
        self._save(item)

    def _skip(self, item: _Schedule, due: dt.datetime, reason: str) -> None:
        log.warning("schedule %s: the start due at %s is skipped: %s", item.id, _iso(due),
                    reason)
        item.due, item.busy_logged = None, ""
        item.last = {"due": _iso(due), "outcome": "skipped", "reason": reason}
        self._pending.append(events.ScheduleSkipped(
            self._runtime.now(), item.id, item.task_id, _iso(due) or "", reason))
        self._save(item)

    def _save(self, item: _Schedule) -> None:
        item.updated = self._runtime.calendar_iso()
        try:
            self._runtime.store.put_schedule(item.record())
        except (StorageError, NotFound) as exc:
            log.error("schedule %s not stored: %s", item.id, exc)

    def _find(self, schedule_id: str) -> _Schedule:
        return look_up(self._schedules, "schedule", schedule_id)

    def _require_stored_task(self, task_id: str) -> None:
        task = self._engine.find(task_id)
        if task.temporary or task.spec is None:
            raise Conflict(f"task {task_id} is not kept in the site store (temporary, or a "
                           "dialect's own tree): it cannot be scheduled")
