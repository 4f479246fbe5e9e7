"""The automation task endpoints (galileo-tasks-bt-ws §6): Galileo's Blockly tasks, kept and run
by the robot's automation tasks (``runtime.automations``).

The object (A-18, inferred): ``id``, ``title``, ``description``, ``py``, ``blocklyxml``,
``is_enabled``, ``api_key`` (the key a ``blockly_action`` triggers it by: given, or read from the
API block of its XML; ``null`` if none) and ``state``, its last run's (``WAITTING`` before one,
``WORKING``, ``COMPLETE``, ``ERROR``, ``CANCELLED``). Lists are arrays (A-5); a delete answers
``{"status": "ok"}`` (A-11). Runs need polynav started with automations on; a program sent
while they are off is kept, not run.
"""

from __future__ import annotations

from typing import Any

from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.endpoint import Reply, RouteList
from polynav.protocols.galileo.params import Params
from polynav.runtime.automation_tasks import trigger_key
from polynav.store.records import AutomationRecord

ROUTES = RouteList()

_TEXT = ("py", "blocklyxml", "title", "description")


def _render(ctx: Context, record: AutomationRecord) -> dict[str, Any]:
    return {"id": record.id, "title": record.title, "description": record.description,
            "py": record.py, "blocklyxml": record.blocklyxml, "is_enabled": record.is_enabled,
            "api_key": trigger_key(record), "state": ctx.runtime.automations.state(record.id)}


def _fields(params: Params, *, required: bool) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for name in _TEXT:
        value = params.text(name) if required else params.text(name, None)
        if value is not None:
            out[name] = value
    enabled = params.boolean("is_enabled") if required else params.boolean("is_enabled", None)
    if enabled is not None:
        out["is_enabled"] = enabled
    key = params.text("api_key", None)
    if key is not None:
        out["api_key"] = key
    return out


@ROUTES.get("/blockly_task")
def get_blockly_tasks(ctx: Context, params: Params) -> Reply:
    """§6.1: every automation task, in an array."""
    return [_render(ctx, r) for r in ctx.runtime.automations.records()]


@ROUTES.post("/blockly_task")
def post_blockly_task(ctx: Context, params: Params) -> Reply:
    """§6.2: a new automation task (run at once if enabled and not triggered by a key)."""
    return _render(ctx, ctx.runtime.automations.create(_fields(params, required=True)))


@ROUTES.put("/blockly_task")
def put_blockly_task(ctx: Context, params: Params) -> Reply:
    """§6.3: change the fields given, keep the others."""
    automation_id = params.text("id")
    fields = _fields(params, required=False)
    return _render(ctx, ctx.runtime.automations.update(automation_id, fields))


@ROUTES.delete("/blockly_task")
def delete_blockly_task(ctx: Context, params: Params) -> Reply:
    """§6.4: forget an automation task (stopping a run of it)."""
    ctx.runtime.automations.delete(params.text("id"))
    return {"status": "ok"}
