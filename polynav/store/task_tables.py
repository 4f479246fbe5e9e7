"""Tasks, their schedules and automation tasks of the site store.

A task is stored as the JSON form its tree was given in (never the live tree): that is what
:func:`polynav.tasks.tree.build` rebuilds it from after a restart, and what a dialect gave and
may read back. Each write is one transaction; a schedule goes with its task (``ON DELETE
CASCADE``), so a task is never deleted leaving a schedule that starts nothing.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from typing import Any

from polynav.errors import InvalidRequest, NotFound
from polynav.store.database import SiteDatabase
from polynav.store.records import AutomationRecord, ScheduleRecord, TaskRecord
from polynav.store.rows import check_name, from_json, to_json

log = logging.getLogger(__name__)

_TASK_COLUMNS = "id, name, owner, kind, spec, blackboard, state, note, updated"
_SCHEDULE_COLUMNS = "id, task_id, spec, enabled, starts, next_fire, updated"
_AUTOMATION_COLUMNS = "id, title, description, py, blocklyxml, is_enabled, api_key, created"


def _task(row: Sequence[Any]) -> TaskRecord:
    return TaskRecord(row[0], row[1], row[2], row[3], from_json(row[4]), from_json(row[5]),
                      row[6], row[7], row[8])


def _schedule(row: Sequence[Any]) -> ScheduleRecord:
    return ScheduleRecord(row[0], row[1], from_json(row[2]), bool(row[3]), int(row[4]), row[5],
                          row[6])


def _automation(row: Sequence[Any]) -> AutomationRecord:
    return AutomationRecord(row[0], row[1], row[2], row[3], row[4], bool(row[5]), row[6],
                            float(row[7]))


class TaskTables(SiteDatabase):
    """Tasks, schedules and automation tasks."""

    # ---------------------------------------------------------------- tasks

    def tasks(self) -> list[TaskRecord]:
        """Every stored task, oldest change first."""
        with self._read() as conn:
            rows = conn.execute(
                f"SELECT {_TASK_COLUMNS} FROM tasks ORDER BY updated, rowid").fetchall()
        return [_task(r) for r in rows]

    def task(self, task_id: str) -> TaskRecord:
        """Raises NotFound: no such stored task."""
        with self._read() as conn:
            row = conn.execute(f"SELECT {_TASK_COLUMNS} FROM tasks WHERE id = ?",
                               (task_id,)).fetchone()
        if row is None:
            raise NotFound("task", task_id)
        return _task(row)

    def put_task(self, record: TaskRecord) -> None:
        """Store ``record``, replacing the task of that id (its schedules stay).

        Raises:
            InvalidRequest: an empty id, or a spec or blackboard that is not JSON.
        """
        check_name("task.id", record.id)
        row = (record.id, record.name, record.owner, record.kind,
               to_json("task.spec", record.spec), to_json("task.blackboard", record.blackboard),
               record.state, record.note, record.updated)
        with self._write() as conn:
            # An upsert, not INSERT OR REPLACE: a replace deletes the row first, and the
            # cascade would take the task's schedules with it.
            conn.execute(
                f"INSERT INTO tasks ({_TASK_COLUMNS}) VALUES (?,?,?,?,?,?,?,?,?) "
                "ON CONFLICT (id) DO UPDATE SET name = excluded.name, owner = excluded.owner, "
                "kind = excluded.kind, spec = excluded.spec, blackboard = excluded.blackboard, "
                "state = excluded.state, note = excluded.note, updated = excluded.updated",
                row)

    def set_task_state(self, task_id: str, state: str, note: str, updated: str) -> None:
        """Record a stored task's last state (nothing for a task that is not stored)."""
        with self._write() as conn:
            conn.execute("UPDATE tasks SET state = ?, note = ?, updated = ? WHERE id = ?",
                         (state, note, updated, task_id))

    def delete_task(self, task_id: str) -> None:
        """Forget a stored task and its schedules (nothing when it is not stored)."""
        with self._write() as conn:
            conn.execute("DELETE FROM tasks WHERE id = ?", (task_id,))

    # ---------------------------------------------------------------- schedules

    def schedules(self, task_id: str | None = None) -> list[ScheduleRecord]:
        """Stored schedules (of one task with ``task_id``), in the order they were made."""
        query = f"SELECT {_SCHEDULE_COLUMNS} FROM schedules"
        args: tuple[str, ...] = ()
        if task_id is not None:
            query, args = query + " WHERE task_id = ?", (task_id,)
        with self._read() as conn:
            rows = conn.execute(query + " ORDER BY rowid", args).fetchall()
        return [_schedule(r) for r in rows]

    def schedule(self, schedule_id: str) -> ScheduleRecord:
        """Raises NotFound: no such schedule."""
        with self._read() as conn:
            row = conn.execute(f"SELECT {_SCHEDULE_COLUMNS} FROM schedules WHERE id = ?",
                               (schedule_id,)).fetchone()
        if row is None:
            raise NotFound("schedule", schedule_id)
        return _schedule(row)

    def put_schedule(self, record: ScheduleRecord) -> None:
        """Store ``record``, replacing the schedule of that id.

        Raises:
            InvalidRequest: an empty id, or a spec that is not JSON.
            NotFound: its task is not stored.
        """
        check_name("schedule.id", record.id)
        row = (record.id, record.task_id, to_json("schedule.spec", record.spec),
               int(record.enabled), int(record.starts), record.next_fire, record.updated)
        with self._write() as conn:
            if conn.execute("SELECT 1 FROM tasks WHERE id = ?",
                            (record.task_id,)).fetchone() is None:
                raise NotFound("task", record.task_id)
            conn.execute(f"INSERT OR REPLACE INTO schedules ({_SCHEDULE_COLUMNS}) "
                         "VALUES (?,?,?,?,?,?,?)", row)

    def delete_schedule(self, schedule_id: str) -> None:
        """Raises NotFound: no such schedule."""
        with self._write() as conn:
            if conn.execute("DELETE FROM schedules WHERE id = ?",
                            (schedule_id,)).rowcount == 0:
                raise NotFound("schedule", schedule_id)

    # ---------------------------------------------------------------- automation tasks

    def automations(self) -> list[AutomationRecord]:
        """Every automation task, oldest first."""
        with self._read() as conn:
            rows = conn.execute(f"SELECT {_AUTOMATION_COLUMNS} FROM automations "
                                "ORDER BY created, rowid").fetchall()
        return [_automation(r) for r in rows]

    def automation(self, automation_id: str) -> AutomationRecord:
        """Raises NotFound: no such automation task."""
        with self._read() as conn:
            row = conn.execute(f"SELECT {_AUTOMATION_COLUMNS} FROM automations WHERE id = ?",
                               (automation_id,)).fetchone()
        if row is None:
            raise NotFound("automation", automation_id)
        return _automation(row)

    def put_automation(self, record: AutomationRecord) -> AutomationRecord:
        """Store ``record`` (a new one, or replacing the one of its id); what was stored.

        Raises:
            InvalidRequest: an empty id, or a field of the wrong type.
        """
        check_name("automation.id", record.id)
        for field in ("title", "description", "py", "blocklyxml"):
            if not isinstance(getattr(record, field), str):
                raise InvalidRequest(f"automation.{field}", "must be a string")
        if record.api_key is not None and not isinstance(record.api_key, str):
            raise InvalidRequest("automation.api_key", "must be a string or null")
        row = (record.id, record.title, record.description, record.py, record.blocklyxml,
               int(bool(record.is_enabled)), record.api_key, float(record.created))
        with self._write() as conn:
            conn.execute(f"INSERT OR REPLACE INTO automations ({_AUTOMATION_COLUMNS}) "
                         "VALUES (?,?,?,?,?,?,?,?)", row)
        return self.automation(record.id)

    def delete_automation(self, automation_id: str) -> None:
        """Raises NotFound: no such automation task."""
        with self._write() as conn:
            if conn.execute("DELETE FROM automations WHERE id = ?",
                            (automation_id,)).rowcount == 0:
                raise NotFound("automation", automation_id)
