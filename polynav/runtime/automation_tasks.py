"""Automation tasks of one robot: their records in the site store, and their runs.

An automation task (Galileo's ``blockly_task``) is a program with a title, a description, the
Blockly workspace it came from, whether it is enabled, and the key that triggers it. Runs are
:mod:`polynav.automation.runner`'s (a separate, limited process each).

When one runs: an enabled automation with a trigger key runs each time it is triggered (a
``blockly_action`` of a task naming the key, or the native API); an enabled one without a key
runs when it is enabled (made or changed to enabled). Disabled ones never run. The key is the
record's ``api_key`` when given, else the first ``<field name="api_key">`` of its Blockly XML
(the API block of Galileo's editor). A key triggers at most one automation: a second enabled
automation with a key already taken is refused.
"""

from __future__ import annotations

import logging
import re
import time
import uuid
from collections.abc import Mapping
from dataclasses import replace
from typing import TYPE_CHECKING, Any

from polynav.automation.runner import AutomationRunner
from polynav.errors import Conflict, InvalidRequest, NotFound
from polynav.store.records import AutomationRecord

if TYPE_CHECKING:
    from polynav.runtime.robot_runtime import RobotRuntime

log = logging.getLogger(__name__)

_API_FIELD = re.compile(r"<field\s+name=\"api_key\"\s*>([^<]{1,200})</field>")
_TEXT_FIELDS = ("title", "description", "py", "blocklyxml")


def trigger_key(record: AutomationRecord) -> str | None:
    """The key that triggers ``record`` (see the module docstring)."""
    if record.api_key:
        return record.api_key
    found = _API_FIELD.search(record.blocklyxml)
    return found.group(1).strip() or None if found else None


class AutomationTasks:
    """``runtime.automations``: records, triggers and runs."""

    def __init__(self, runtime: RobotRuntime, runner: AutomationRunner) -> None:
        self._runtime = runtime
        self.runner = runner

    # -- records -------------------------------------------------------------------------

    def records(self) -> list[AutomationRecord]:
        return list(self._runtime.store.automations())

    def record(self, automation_id: str) -> AutomationRecord:
        """Raises NotFound."""
        return self._runtime.store.automation(automation_id)

    def create(self, fields: Mapping[str, Any]) -> AutomationRecord:
        """A new automation from ``title``, ``description``, ``py``, ``blocklyxml``,
        ``is_enabled`` (all required) and ``api_key`` (optional); run if enabled with no key.

        Raises:
            InvalidRequest: a field missing or of the wrong type; a key another enabled
                automation has.
        """
        for name in (*_TEXT_FIELDS, "is_enabled"):
            if name not in fields:
                raise InvalidRequest(name, "is required")
        record = AutomationRecord(id=str(uuid.uuid4()), api_key=None, created=time.time(),
                                  **{k: fields[k] for k in (*_TEXT_FIELDS, "is_enabled")})
        return self._put(replace(record, api_key=fields.get("api_key")), was_enabled=False)

    def update(self, automation_id: str, fields: Mapping[str, Any]) -> AutomationRecord:
        """Change the given fields (the others kept); run if it became enabled with no key.

        Raises:
            NotFound: no such automation. InvalidRequest: as for :meth:`create`.
        """
        old = self.record(automation_id)
        changes = {k: fields[k] for k in (*_TEXT_FIELDS, "is_enabled", "api_key") if k in fields}
        return self._put(replace(old, **changes), was_enabled=old.is_enabled)

    def delete(self, automation_id: str) -> None:
        """Forget an automation (stopping its run). Raises NotFound."""
        self.record(automation_id)
        for run in self.runner.runs(automation_id):
            if run["state"] == "WORKING":
                self.runner.stop(run["id"])
        self._runtime.store.delete_automation(automation_id)

    def _put(self, record: AutomationRecord, *, was_enabled: bool) -> AutomationRecord:
        for name in _TEXT_FIELDS:
            if not isinstance(getattr(record, name), str):
                raise InvalidRequest(name, "must be a string")
        if not isinstance(record.is_enabled, bool):
            raise InvalidRequest("is_enabled", "must be true or false")
        if record.api_key is not None and not (isinstance(record.api_key, str)
                                               and record.api_key.strip()):
            raise InvalidRequest("api_key", "must be a non-empty string or null")
        key = trigger_key(record)
        if record.is_enabled and key is not None:
            for other in self.records():
                if other.id != record.id and other.is_enabled and trigger_key(other) == key:
                    raise InvalidRequest("api_key", f"{key!r} already triggers automation "
                                                    f"{other.id} ({other.title!r})")
        stored = self._runtime.store.put_automation(record)
        if stored.is_enabled and not was_enabled and key is None and self.runner.enabled:
            self.runner.start(stored.id, stored.py)
        return stored

    # -- runs ----------------------------------------------------------------------------

    def start(self, automation_id: str) -> dict[str, Any]:
        """Run an automation now.

        Raises:
            NotFound: no such automation. Conflict: it is disabled, automations are off, or it
                runs already.
        """
        record = self.record(automation_id)
        if not record.is_enabled:
            raise Conflict(f"automation {automation_id} is disabled")
        return self.runner.start(record.id, record.py)

    def trigger(self, key: str) -> dict[str, Any]:
        """Run the enabled automation that ``key`` triggers; its run.

        Raises:
            NotFound: no enabled automation has that key. Conflict: as :meth:`start`.
        """
        for record in self.records():
            if record.is_enabled and trigger_key(record) == key:
                return self.runner.start(record.id, record.py)
        raise NotFound("automation with api_key", key)

    def state(self, automation_id: str) -> str:
        """``WORKING`` while a run of it runs, else its last run's end, else ``WAITTING``."""
        runs = self.runner.runs(automation_id)
        return runs[-1]["state"] if runs else "WAITTING"

    def close(self) -> None:
        self.runner.close()
